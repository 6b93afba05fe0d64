#pragma once

// ParamReader: typed, validated access to one component's parameters, as the launch
// loader hands them over. A component's read_config() asks for each field with its
// allowed range; every problem is collected with the file, the line, the key and what is
// allowed, so a bad launch file fails at start-up with all its errors at once.
// YAML stays inside this class: components and algorithms only see typed values.

#include <initializer_list>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/enum_names.hpp"

namespace scancrew {

struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
};

class ParamReader {
 public:
  struct Impl;
  explicit ParamReader(std::unique_ptr<Impl> impl);
  ~ParamReader();
  ParamReader(ParamReader&&) noexcept;
  ParamReader& operator=(ParamReader&&) noexcept;

  // A reader over a YAML mapping given as text (tests, `--set` overrides).
  static ParamReader from_yaml_string(const std::string& text, const std::string& where);

  // Supported T: double, int, int64_t, uint32_t, uint64_t, bool, std::string.
  // optional(): a missing key keeps `value` (the default); required(): it is an error.
  template <class T>
  void optional(std::string_view key, T& value, Range range = {});
  template <class T>
  void required(std::string_view key, T& value, Range range = {});
  // A string that must be one of `allowed`.
  void choice(std::string_view key, std::string& value,
              std::initializer_list<std::string_view> allowed, bool is_required = false);
  // An enum named as one of `names` (core/enum_names.hpp); the error lists them.
  template <class E, size_t N>
  void choice(std::string_view key, E& value, const EnumNames<E, N>& names,
              bool is_required = false) {
    std::vector<std::string_view> allowed;
    allowed.reserve(N);
    for (const auto& n : names) allowed.push_back(n.name);
    std::string picked(name_of(names, value));
    if (choose(key, picked, allowed, is_required)) value = *value_of(names, picked);
  }
  // A list of numbers; `size` 0 means any length.
  void optional_list(std::string_view key, std::vector<double>& value, size_t size = 0,
                     Range range = {});
  // A list of strings (topic names, file names).
  void optional_list(std::string_view key, std::vector<std::string>& value);

  // Reports keys that no read asked for (typos). Call after the last read.
  void finish();
  // Declares a key read by other means (a nested list), so finish() accepts it.
  void mark_known(std::string_view key) { asked_.emplace_back(key); }
  // Reports a problem with a key that the typed reads cannot see (a missing file, say).
  void report(std::string_view key, const std::string& message) { error(key, message); }

  bool ok() const { return errors_.empty(); }
  const std::vector<std::string>& errors() const { return errors_; }
  // "file:line: path" of this mapping, the prefix of every message.
  std::string where() const;

 private:
  template <class T>
  void read(std::string_view key, T& value, Range range, bool is_required);
  // Reads `key` into `value` if it is one of `allowed`; false (and an error) if not.
  bool choose(std::string_view key, std::string& value,
              const std::vector<std::string_view>& allowed, bool is_required);
  void error(std::string_view key, const std::string& message);

  std::unique_ptr<Impl> impl_;
  std::vector<std::string> errors_;
  std::vector<std::string> asked_;
};

}  // namespace scancrew
