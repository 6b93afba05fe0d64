#include "executors/registry.hpp"

#include "core/check.hpp"
#include "executors/params_impl.hpp"

namespace scancrew {

ComponentRegistry& ComponentRegistry::instance() {
  static ComponentRegistry registry;
  return registry;
}

bool ComponentRegistry::add(const std::string& type, Factory factory, std::string description,
                            bool world, ParamsReader read_params) {
  const bool inserted =
      entries_.emplace(type, Entry{std::move(factory), std::move(description), world, read_params})
          .second;
  SCANCREW_CHECK(inserted, "two components registered under one name");
  return inserted;
}

const ComponentRegistry::Entry* ComponentRegistry::find(const std::string& type) const {
  auto it = entries_.find(type);
  return it == entries_.end() ? nullptr : &it->second;
}

std::vector<ParamInfo> ComponentRegistry::parameters(const std::string& type) const {
  const Entry* entry = find(type);
  if (entry == nullptr || entry->read_params == nullptr) return {};
  ParamReader reader = ParamReader::describing();
  entry->read_params(reader);
  return reader.described();
}

std::vector<ParamInfo> ComponentRegistry::effective_parameters(const std::string& type,
                                                               const YAML::Node& params) const {
  const Entry* entry = find(type);
  if (entry == nullptr || entry->read_params == nullptr) return {};
  ParamReader reader = make_param_reader(params, "(effective)", "params");
  entry->read_params(reader);
  return reader.effective();
}

std::vector<std::string> ComponentRegistry::types() const {
  std::vector<std::string> out;
  for (const auto& [name, entry] : entries_) out.push_back(name);
  return out;
}

}  // namespace scancrew
