#pragma once

// find_component<T>(launch): the first component of type T in a composed launch (null if
// none), for tests that read a component's counters after a run.

#include "executors/launch.hpp"

namespace scancrew::test {

template <class T>
T* find_component(const Launch& launch) {
  for (const auto& c : launch.components())
    if (auto* t = dynamic_cast<T*>(c.get())) return t;
  return nullptr;
}

}  // namespace scancrew::test
