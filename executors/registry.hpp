#pragma once

// ComponentRegistry: component types by name, filled at link time by
// SCANCREW_REGISTER_COMPONENT in each component's source file (no plugins, no dlopen).
// Component libraries are linked whole-archive so their registrations are kept.
//
// A registered class C provides:
//   static constexpr std::string_view kDescription;    // one line for `scancrew components`
//   struct Config { ... };                             // plain struct with defaults
//   static Config read_config(ParamReader&);           // typed, validated parameters; run
//                                                       // over ParamReader::describing() it
//                                                       // lists them (`scancrew components
//                                                       // NAME`, docs/parameters.md)
//   C(ComponentContext, Config);
//   static constexpr bool kWorld = true;                // optional: not on any robot or
//                                                       // station (the simulator, the
//                                                       // mission's instruments): its
//                                                       // compute is never charged
// Thread safety: registration happens during static initialisation; lookups after main().

#include <yaml-cpp/node/node.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "executors/component.hpp"
#include "executors/params.hpp"

namespace scancrew {

class ComponentRegistry {
 public:
  // Builds a component from its parameters, or returns the parameter errors.
  using Factory = std::function<Result<std::unique_ptr<Component>, std::vector<std::string>>(
      ComponentContext, ParamReader&)>;
  // Runs the type's read_config() over a reader (ParamReader::describing()).
  using ParamsReader = void (*)(ParamReader&);
  struct Entry {
    Factory factory;
    std::string description;
    bool world = false;  // C::kWorld (StepExecutor, compute_time: charged)
    ParamsReader read_params = nullptr;
  };

  static ComponentRegistry& instance();

  bool add(const std::string& type, Factory factory, std::string description, bool world = false,
           ParamsReader read_params = nullptr);
  const Entry* find(const std::string& type) const;
  std::vector<std::string> types() const;
  // The parameters of `type`, as its read_config() asks for them, in that order; empty for a
  // type not registered or registered without read_params.
  std::vector<ParamInfo> parameters(const std::string& type) const;
  // The value of every parameter of `type` given `params` (a launch file's params mapping):
  // its read_config() run over them, each key with the value it read or defaulted to
  // (ParamReader::effective()); empty as parameters() is.
  std::vector<ParamInfo> effective_parameters(const std::string& type,
                                              const YAML::Node& params) const;

 private:
  std::map<std::string, Entry> entries_;
};

template <class C>
Result<std::unique_ptr<Component>, std::vector<std::string>> make_component(
    ComponentContext context, ParamReader& params) {
  typename C::Config config = C::read_config(params);
  params.finish();
  if (!params.ok()) return make_unexpected(params.errors());
  return std::unique_ptr<Component>(std::make_unique<C>(std::move(context), std::move(config)));
}

template <class C>
void read_component_params(ParamReader& params) {
  (void)C::read_config(params);
}

template <class C>
constexpr bool is_world_component() {
  if constexpr (requires { C::kWorld; })
    return C::kWorld;
  else
    return false;
}

}  // namespace scancrew

#define SCANCREW_REGISTER_COMPONENT(Class, type_name)                                          \
  namespace {                                                                                  \
  [[maybe_unused]] const bool scancrew_registered_##Class =                                    \
      ::scancrew::ComponentRegistry::instance().add(                                           \
          type_name, &::scancrew::make_component<Class>, std::string(Class::kDescription),     \
          ::scancrew::is_world_component<Class>(), &::scancrew::read_component_params<Class>); \
  }
