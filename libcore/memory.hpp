#pragma once
// Memory available to this process, so that big allocations (voxel images, scenes) can be
// refused up front with the numbers instead of failing half-way with std::bad_alloc or the
// kernel's OOM killer.
#include <cstdint>
#include <string>

namespace poresph {

/// MemAvailable from /proc/meminfo in bytes (the kernel's estimate of what can be allocated
/// without swapping); 0 when unknown (no /proc, other systems): callers then skip their check.
std::uint64_t availableMemoryBytes();

/// Human-readable size with binary units, e.g. "512 B", "3.2 GiB".
std::string formatBytes(std::uint64_t bytes);

}  // namespace poresph
