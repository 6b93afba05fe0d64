#pragma once

// ParamReader: typed, validated access to one component's parameters, as the launch
// loader hands them over. A component's read_config() asks for each field with its
// allowed range; every problem is collected with the file, the line, the key and what is
// allowed, so a bad launch file fails at start-up with all its errors at once.
// YAML stays inside this class: components and algorithms only see typed values.
//
// A reader made by describing() reads no file: each read records the parameter (its key,
// C++ type, the value before the read = its default, range, allowed names, whether it is
// required) and keeps the value, and nothing is an error. `scancrew components NAME` and
// docs/parameters.md run a component's read_config() over it, so the one list of a
// component's parameters is its read_config(). A read's .doc("...") gives the parameter's
// one-line description, kept beside the read: p.optional("rate_hz", c.rate_hz, {0, 100})
//     .doc("camera frame rate (Hz)");

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

// One parameter as read_config() asks for it, recorded by a describing() reader.
struct ParamInfo {
  std::string key;
  std::string type;                  // double, int, int64, uint32, uint64, bool, string, choice,
                                     // list<double>, list<string>
  std::string default_value;         // the value before the read
  std::string range;                 // "[0, 10]", ">= 1", "<= 5", or "" (any)
  std::vector<std::string> allowed;  // a choice's names
  bool required = false;
  std::string description;  // from .doc(), or "" when the read has none
};

// What a read returns: doc() sets the parameter's description when the reader describes,
// and does nothing otherwise (a launch file's reads cost nothing more).
class ParamDoc {
 public:
  ParamDoc() = default;
  ParamDoc(std::vector<ParamInfo>* described, size_t index)
      : described_(described), index_(index) {}
  void doc(std::string_view text) const {
    if (described_ != nullptr) (*described_)[index_].description = text;
  }

 private:
  std::vector<ParamInfo>* described_ = nullptr;
  size_t index_ = 0;
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
  // A reader that records each read instead of reading (see above); described() lists them.
  static ParamReader describing();
  bool is_describing() const { return describing_; }
  const std::vector<ParamInfo>& described() const { return described_; }
  // Every key a (non-describing) read asked for, with the value it left: the launch file's,
  // or the default. ParamInfo::default_value holds it as YAML text that reads back exactly
  // (doubles in shortest round-trip form, lists as flow sequences). A non-finite double
  // (a default meaning "none") is left out: no launch file can give it.
  const std::vector<ParamInfo>& effective() const { return effective_; }

  // Supported T: double, int, int64_t, uint32_t, uint64_t, bool, std::string.
  // optional(): a missing key keeps `value` (the default); required(): it is an error.
  template <class T>
  ParamDoc optional(std::string_view key, T& value, Range range = {});
  template <class T>
  ParamDoc required(std::string_view key, T& value, Range range = {});
  // A string that must be one of `allowed`.
  ParamDoc choice(std::string_view key, std::string& value,
                  std::initializer_list<std::string_view> allowed, bool is_required = false);
  // An enum named as one of `names` (core/enum_names.hpp); the error lists them.
  template <class E, size_t N>
  ParamDoc choice(std::string_view key, E& value, const EnumNames<E, N>& names,
                  bool is_required = false) {
    std::vector<std::string_view> allowed;
    allowed.reserve(N);
    for (const auto& n : names) allowed.push_back(n.name);
    std::string picked(name_of(names, value));
    if (choose(key, picked, allowed, is_required)) value = *value_of(names, picked);
    return doc_of(key);
  }
  // A list of numbers; `size` 0 means any length.
  ParamDoc optional_list(std::string_view key, std::vector<double>& value, size_t size = 0,
                         Range range = {});
  // A list of strings (topic names, file names).
  ParamDoc optional_list(std::string_view key, std::vector<std::string>& value);

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
  template <class T>
  void read_value(std::string_view key, T& value, Range range, bool is_required);
  ParamDoc read_list(std::string_view key, std::vector<double>& value, size_t size, Range range);
  ParamDoc read_list(std::string_view key, std::vector<std::string>& value);
  // describing(): records a read (once per key); the doc handle of `key`'s record.
  void record(ParamInfo info);
  // A non-describing read's outcome (effective()).
  void note_effective(std::string_view key, std::string type, std::string yaml_text);
  ParamDoc doc_of(std::string_view key);
  // Reads `key` into `value` if it is one of `allowed`; false (and an error) if not.
  bool choose(std::string_view key, std::string& value,
              const std::vector<std::string_view>& allowed, bool is_required);
  void error(std::string_view key, const std::string& message);

  std::unique_ptr<Impl> impl_;
  std::vector<std::string> errors_;
  std::vector<std::string> asked_;
  bool describing_ = false;
  std::vector<ParamInfo> described_;
  std::vector<ParamInfo> effective_;
};

}  // namespace scancrew
