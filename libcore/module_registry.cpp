#include <cstdio>
#include <map>

#include "libcore/module.hpp"

namespace poresph {

std::string settingNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

namespace {
std::map<std::string, ModuleRegistry::Factory>& registry() {
  static std::map<std::string, ModuleRegistry::Factory> r;
  return r;
}
}  // namespace

bool ModuleRegistry::add(const std::string& name, Factory factory) {
  registry()[name] = std::move(factory);
  return true;
}

std::unique_ptr<Module> ModuleRegistry::create(const std::string& name) {
  auto it = registry().find(name);
  if (it == registry().end()) throw InputError("no physics module named '" + name + "'");
  return it->second();
}

std::vector<std::string> ModuleRegistry::names() {
  std::vector<std::string> out;
  for (const auto& kv : registry()) out.push_back(kv.first);
  return out;
}

std::string ModuleRegistry::moduleForModel(const std::string& model) {
  for (const auto& kv : registry()) {
    auto m = kv.second();
    for (const auto& name : m->materialModels())
      if (name == model) return kv.first;
  }
  return "";
}

}  // namespace poresph
