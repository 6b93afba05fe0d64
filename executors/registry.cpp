#include "executors/registry.hpp"

#include "core/check.hpp"

namespace scancrew {

ComponentRegistry& ComponentRegistry::instance() {
  static ComponentRegistry registry;
  return registry;
}

bool ComponentRegistry::add(const std::string& type, Factory factory, std::string description,
                            bool world) {
  const bool inserted =
      entries_.emplace(type, Entry{std::move(factory), std::move(description), world}).second;
  SCANCREW_CHECK(inserted, "two components registered under one name");
  return inserted;
}

const ComponentRegistry::Entry* ComponentRegistry::find(const std::string& type) const {
  auto it = entries_.find(type);
  return it == entries_.end() ? nullptr : &it->second;
}

std::vector<std::string> ComponentRegistry::types() const {
  std::vector<std::string> out;
  for (const auto& [name, entry] : entries_) out.push_back(name);
  return out;
}

}  // namespace scancrew
