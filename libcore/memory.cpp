#include "libcore/memory.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace poresph {

std::uint64_t availableMemoryBytes() {
  std::ifstream in("/proc/meminfo");
  std::string line;
  while (std::getline(in, line)) {
    // "MemAvailable:   12345678 kB"
    if (line.rfind("MemAvailable:", 0) != 0) continue;
    std::istringstream s(line.substr(13));
    std::uint64_t kib = 0;
    std::string unit;
    if (!(s >> kib)) return 0;
    s >> unit;
    return unit == "kB" ? kib * 1024 : kib;
  }
  return 0;
}

std::string formatBytes(std::uint64_t bytes) {
  static const char* const units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  if (bytes < 1024) return std::to_string(bytes) + " B";
  double v = static_cast<double>(bytes);
  int u = 0;
  while (v >= 1024.0 && u < 6) v /= 1024.0, ++u;
  char buf[32];
  std::snprintf(buf, sizeof(buf), v < 10.0 ? "%.2f %s" : (v < 100.0 ? "%.1f %s" : "%.0f %s"), v,
                units[u]);
  return buf;
}

}  // namespace poresph
