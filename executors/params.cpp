#include "executors/params.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "executors/params_impl.hpp"

namespace scancrew {

std::string yaml_location(const std::string& file, const YAML::Node& node) {
  if (!node.IsDefined() || node.Mark().line < 0) return file;
  return file + ":" + std::to_string(node.Mark().line + 1);
}

namespace {

// The first key a mapping under `node` holds twice ("file:line: duplicate key 'k' (first at
// line n)"), or "". yaml-cpp keeps both entries and a lookup finds the first, so the second
// was silently ignored. Depth-first, iterative (a hostile file may nest deeply). Each node
// the text spells takes a byte of it at least, and an alias (`*a`, ~3 bytes) repeats its
// anchor's nodes: a walk of more than 64 nodes per byte is aliases expanding aliases (a
// "billion laughs" file: 33 M nodes from 0.6 KB), and refused.
std::string duplicate_key(const YAML::Node& root, const std::string& label, size_t text_bytes) {
  std::vector<YAML::Node> stack{root};
  size_t visits = 0;
  while (!stack.empty()) {
    if (++visits > 64 * text_bytes + 1024)
      return label + ": its aliases expand to more nodes than it has bytes; refused";
    const YAML::Node node = stack.back();
    stack.pop_back();
    if (node.IsSequence()) {
      for (const auto& child : node) stack.push_back(child);
    } else if (node.IsMap()) {
      std::map<std::string, int> lines;
      for (const auto& kv : node) {
        if (kv.first.IsScalar()) {
          const auto [it, fresh] = lines.emplace(kv.first.Scalar(), kv.first.Mark().line + 1);
          if (!fresh)
            return label + ":" + std::to_string(kv.first.Mark().line + 1) + ": duplicate key '" +
                   kv.first.Scalar() + "' (first at line " + std::to_string(it->second) + ")";
        }
        stack.push_back(kv.second);
      }
    }
  }
  return {};
}

}  // namespace

Result<YAML::Node, std::string> parse_yaml(const std::string& text, const std::string& label) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return make_unexpected(label + ":" + std::to_string(e.mark.line + 1) +
                           ": not valid YAML: " + e.msg);
  }
  if (std::string dup = duplicate_key(root, label, text.size()); !dup.empty())
    return make_unexpected(dup);
  return root;
}

Result<std::string, std::string> read_text_file(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  // a folder that may not be searched is not "no such file": give the system's reason
  if (ec && ec != std::errc::no_such_file_or_directory) return make_unexpected(ec.message());
  if (!std::filesystem::exists(status)) return make_unexpected(std::string("no such file"));
  if (!std::filesystem::is_regular_file(status))
    return make_unexpected(std::string("not a regular file (a device, a pipe or a directory)"));
  const uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return make_unexpected("cannot read its size: " + ec.message());
  if (size > kMaxTextFileBytes)
    return make_unexpected(std::to_string(size) + " bytes, over the " +
                           std::to_string(kMaxTextFileBytes >> 20) + " MiB a text file may have");
  std::ifstream in(path, std::ios::binary);
  // NOLINTNEXTLINE(concurrency-mt-unsafe): the message of this thread's errno, read at once
  if (!in) return make_unexpected(std::string("cannot open it: ") + std::strerror(errno));
  std::string text;
  text.resize(static_cast<size_t>(size));
  in.read(text.data(), static_cast<std::streamsize>(size));
  // a file that shrank meanwhile keeps what was read
  text.resize(static_cast<size_t>(in.gcount()));
  return text;
}

std::string substitute(std::string text,
                       const std::vector<std::pair<std::string, std::string>>& substitutions) {
  for (const auto& [from, to] : substitutions) {
    if (from.empty()) continue;
    for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at)) {
      text.replace(at, from.size(), to);
      at += to.size();
    }
  }
  return text;
}

ParamReader make_param_reader(const YAML::Node& node, const std::string& file,
                              const std::string& path,
                              std::vector<std::pair<std::string, std::string>> substitutions) {
  auto impl = std::make_unique<ParamReader::Impl>();
  impl->substitutions = std::move(substitutions);
  // a missing key yields an invalid node in yaml-cpp, on which type queries throw
  impl->node = node.IsDefined() ? node : YAML::Node(YAML::NodeType::Null);
  impl->file = file;
  impl->path = path;
  return ParamReader(std::move(impl));
}

ParamReader::ParamReader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {
  if (impl_->node.IsDefined() && !impl_->node.IsNull() && !impl_->node.IsMap())
    errors_.push_back(where() + ": must be a mapping of key: value");
}
ParamReader::~ParamReader() = default;
ParamReader::ParamReader(ParamReader&&) noexcept = default;
ParamReader& ParamReader::operator=(ParamReader&&) noexcept = default;

ParamReader ParamReader::from_yaml_string(const std::string& text, const std::string& where) {
  auto root = parse_yaml(text, where);
  ParamReader reader = make_param_reader(root ? *root : YAML::Node(), where, "params");
  if (!root) reader.errors_.push_back(root.error());
  return reader;
}

ParamReader ParamReader::describing() {
  ParamReader reader = make_param_reader(YAML::Node(), "(described)", "params");
  reader.describing_ = true;
  return reader;
}

void ParamReader::record(ParamInfo info) {
  for (const ParamInfo& known : described_)
    if (known.key == info.key) return;  // read twice (a topic both exported and imported)
  described_.push_back(std::move(info));
}

ParamDoc ParamReader::doc_of(std::string_view key) {
  if (!describing_) return {};
  for (size_t i = 0; i < described_.size(); ++i)
    if (described_[i].key == key) return {&described_, i};
  return {};
}

std::string ParamReader::where() const {
  return yaml_location(impl_->file, impl_->node) + ": " + impl_->path;
}

void ParamReader::error(std::string_view key, const std::string& message) {
  if (describing_) return;  // no values were read: the checks of defaults say nothing
  const YAML::Node& node = impl_->node;
  YAML::Node at = node.IsMap() ? node[std::string(key)] : YAML::Node();
  errors_.push_back(yaml_location(impl_->file, at.IsDefined() ? at : node) + ": " + impl_->path +
                    "." + std::string(key) + ": " + message);
}

namespace {

std::string format_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string describe_range(const char* kind, Range r) {
  std::string s = kind;
  const bool lo = std::isfinite(r.min), hi = std::isfinite(r.max);
  if (lo && hi)
    s += " in [" + format_number(r.min) + ", " + format_number(r.max) + "]";
  else if (lo)
    s += " >= " + format_number(r.min);
  else if (hi)
    s += " <= " + format_number(r.max);
  return s;
}

template <class T>
constexpr const char* kind_name() {
  if constexpr (std::is_same_v<T, bool>)
    return "true or false";
  else if constexpr (std::is_same_v<T, std::string>)
    return "a string";
  else if constexpr (std::is_floating_point_v<T>)
    return "a number";
  else if constexpr (std::is_unsigned_v<T>)
    return "a non-negative integer";
  else
    return "an integer";
}

// A number as the parameter reference shows it: 10 significant digits ("0.6", not the
// 0.6000000000000001 that 3 * 0.2 is; 4294967295 whole).
std::string number_text(double v) {
  std::array<char, 32> text{};
  const int n = std::snprintf(text.data(), text.size(), "%.10g", v);
  return {text.data(), static_cast<size_t>(std::max(n, 0))};
}

// A range as the parameter reference shows it: "[0, 10]", ">= 1", "<= 5" or "".
std::string range_text(Range r) {
  const bool lo = std::isfinite(r.min), hi = std::isfinite(r.max);
  if (lo && hi) return "[" + number_text(r.min) + ", " + number_text(r.max) + "]";
  if (lo) return ">= " + number_text(r.min);
  if (hi) return "<= " + number_text(r.max);
  return {};
}

template <class T>
constexpr const char* type_name() {
  if constexpr (std::is_same_v<T, bool>)
    return "bool";
  else if constexpr (std::is_same_v<T, std::string>)
    return "string";
  else if constexpr (std::is_same_v<T, double>)
    return "double";
  else if constexpr (std::is_same_v<T, int>)
    return "int";
  else if constexpr (std::is_same_v<T, int64_t>)
    return "int64";
  else if constexpr (std::is_same_v<T, uint32_t>)
    return "uint32";
  else
    return "uint64";
}

// A default as the parameter reference shows it.
template <class T>
std::string value_text(const T& value) {
  if constexpr (std::is_same_v<T, bool>) {
    return value ? "true" : "false";
  } else if constexpr (std::is_same_v<T, std::string>) {
    return value;
  } else if constexpr (std::is_floating_point_v<T>) {
    return number_text(value);
  } else {
    std::array<char, 64> text{};
    const auto end = std::to_chars(text.data(), text.data() + text.size(), value).ptr;
    return {text.data(), end};
  }
}

// A value as YAML text that reads back to the same value: doubles in their shortest
// round-trip form (value_text's 10 digits are for people), strings double-quoted.
template <class T>
std::string exact_text(const T& value) {
  if constexpr (std::is_floating_point_v<T>) {
    std::array<char, 64> text{};
    const auto end = std::to_chars(text.data(), text.data() + text.size(), value).ptr;
    return {text.data(), end};
  } else if constexpr (std::is_same_v<T, std::string>) {
    std::string out = "\"";
    for (const char c : value) {
      if (c == '"' || c == '\\') out += '\\';
      out += c;
    }
    return out + "\"";
  } else {
    return value_text(value);
  }
}

template <class T>
std::string exact_list_text(const std::vector<T>& values) {
  std::string out;
  for (const T& v : values) out += (out.empty() ? "" : ", ") + exact_text(v);
  return "[" + out + "]";
}

template <class T>
Range clamp_range(Range r) {
  if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
    r.min = std::max(r.min, static_cast<double>(std::numeric_limits<T>::lowest()));
    r.max = std::min(r.max, static_cast<double>(std::numeric_limits<T>::max()));
  }
  return r;
}

// Parses a scalar strictly: "3.5" is not an integer, "yes" is not a number.
template <class T>
bool parse_scalar(const std::string& text, T& out) {
  if constexpr (std::is_same_v<T, std::string>) {
    out = text;
    return true;
  } else if constexpr (std::is_same_v<T, bool>) {
    if (text == "true" || text == "True" || text == "TRUE") return out = true, true;
    if (text == "false" || text == "False" || text == "FALSE") return out = false, true;
    return false;
  } else {
    std::istringstream s(text);
    s.imbue(std::locale::classic());
    if constexpr (std::is_floating_point_v<T>) {
      double v = 0;
      if (!(s >> v) || !s.eof() || !std::isfinite(v)) return false;
      out = static_cast<T>(v);
    } else {
      long double v = 0;
      if (!(s >> v) || !s.eof() || v != std::floor(v)) return false;
      if (v < static_cast<long double>(std::numeric_limits<T>::lowest()) ||
          v > static_cast<long double>(std::numeric_limits<T>::max()))
        return false;
      out = static_cast<T>(v);
    }
    return true;
  }
}

}  // namespace

template <class T>
void ParamReader::read(std::string_view key, T& value, Range range, bool is_required) {
  read_value(key, value, range, is_required);
  // a non-finite default stands for "none" (no altitude limit, say): no launch file can
  // give it, so effective() leaves it out
  if constexpr (std::is_floating_point_v<T>)
    if (!std::isfinite(value)) return;
  if (!describing_) note_effective(key, type_name<T>(), exact_text(value));
}

template <class T>
void ParamReader::read_value(std::string_view key, T& value, Range range, bool is_required) {
  asked_.emplace_back(key);
  if (describing_) {
    record({.key = std::string(key),
            .type = type_name<T>(),
            .default_value = value_text(value),
            .range = range_text(range),
            .required = is_required});
    return;
  }
  const Range r = clamp_range<T>(range);
  const std::string allowed = std::is_arithmetic_v<T> && !std::is_same_v<T, bool>
                                  ? describe_range(kind_name<T>(), r)
                                  : std::string(kind_name<T>());
  const YAML::Node& node = impl_->node;
  const YAML::Node item = node.IsMap() ? node[std::string(key)] : YAML::Node();
  if (!item.IsDefined() || item.IsNull()) {
    if (is_required) error(key, "missing required parameter; allowed: " + allowed);
    return;
  }
  T parsed{};
  if (!item.IsScalar() || !parse_scalar(item.Scalar(), parsed)) {
    const std::string shown =
        item.IsScalar() ? "'" + item.Scalar() + "'" : std::string("a list or mapping");
    error(key, shown + " has the wrong type; allowed: " + allowed);
    return;
  }
  if constexpr (std::is_same_v<T, std::string>)
    parsed = substitute(std::move(parsed), impl_->substitutions);
  if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
    const auto v = static_cast<double>(parsed);
    if (v < r.min || v > r.max) {
      error(key, item.Scalar() + " is out of range; allowed: " + allowed);
      return;
    }
  }
  value = parsed;
}

template <class T>
ParamDoc ParamReader::optional(std::string_view key, T& value, Range range) {
  read(key, value, range, false);
  return doc_of(key);
}
template <class T>
ParamDoc ParamReader::required(std::string_view key, T& value, Range range) {
  read(key, value, range, true);
  return doc_of(key);
}

// NOLINTBEGIN(bugprone-macro-parentheses): T is a type; parentheses would not parse
#define SCANCREW_PARAM_TYPE(T)                                             \
  template ParamDoc ParamReader::optional<T>(std::string_view, T&, Range); \
  template ParamDoc ParamReader::required<T>(std::string_view, T&, Range);
SCANCREW_PARAM_TYPE(double)
SCANCREW_PARAM_TYPE(int)
SCANCREW_PARAM_TYPE(int64_t)
SCANCREW_PARAM_TYPE(uint32_t)
SCANCREW_PARAM_TYPE(uint64_t)
SCANCREW_PARAM_TYPE(bool)
SCANCREW_PARAM_TYPE(std::string)
#undef SCANCREW_PARAM_TYPE
// NOLINTEND(bugprone-macro-parentheses): end of the explicit instantiations above

ParamDoc ParamReader::choice(std::string_view key, std::string& value,
                             std::initializer_list<std::string_view> allowed, bool is_required) {
  choose(key, value, std::vector<std::string_view>(allowed), is_required);
  return doc_of(key);
}

bool ParamReader::choose(std::string_view key, std::string& value,
                         const std::vector<std::string_view>& allowed, bool is_required) {
  if (describing_) {
    asked_.emplace_back(key);
    record({.key = std::string(key),
            .type = "choice",
            .default_value = value,
            .allowed = {allowed.begin(), allowed.end()},
            .required = is_required});
    return true;
  }
  std::string picked = value;
  read_value(key, picked, {}, is_required);
  std::string list;
  for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
  if (std::find(allowed.begin(), allowed.end(), picked) == allowed.end()) {
    error(key, "'" + picked + "' is not allowed; allowed: " + list);
    return false;
  }
  value = picked;
  note_effective(key, "choice", exact_text(value));
  return true;
}

ParamDoc ParamReader::optional_list(std::string_view key, std::vector<double>& value, size_t size,
                                    Range range) {
  const ParamDoc doc = read_list(key, value, size, range);
  if (!describing_) note_effective(key, "list<double>", exact_list_text(value));
  return doc;
}

ParamDoc ParamReader::optional_list(std::string_view key, std::vector<std::string>& value) {
  const ParamDoc doc = read_list(key, value);
  if (!describing_) note_effective(key, "list<string>", exact_list_text(value));
  return doc;
}

void ParamReader::note_effective(std::string_view key, std::string type, std::string yaml_text) {
  for (ParamInfo& known : effective_)
    if (known.key == key) {
      known.type = std::move(type);
      known.default_value = std::move(yaml_text);
      return;
    }
  effective_.push_back(
      {.key = std::string(key), .type = std::move(type), .default_value = std::move(yaml_text)});
}

ParamDoc ParamReader::read_list(std::string_view key, std::vector<double>& value, size_t size,
                                Range range) {
  asked_.emplace_back(key);
  if (describing_) {
    std::string shown;
    for (const double v : value) shown += (shown.empty() ? "" : ", ") + value_text(v);
    record({.key = std::string(key),
            .type = size ? "list<double> of " + std::to_string(size) : "list<double>",
            .default_value = "[" + shown + "]",
            .range = range_text(range)});
    return doc_of(key);
  }
  const YAML::Node& node = impl_->node;
  const YAML::Node item = node.IsMap() ? node[std::string(key)] : YAML::Node();
  if (!item.IsDefined() || item.IsNull()) return {};
  const std::string allowed =
      (size ? "a list of " + std::to_string(size) + " " : std::string("a list of ")) +
      describe_range("numbers", range);
  if (!item.IsSequence() || (size != 0 && item.size() != size)) {
    error(key, "wrong shape; allowed: " + allowed);
    return {};
  }
  std::vector<double> parsed;
  for (const auto& element : item) {
    double v = 0;
    if (!element.IsScalar() || !parse_scalar(element.Scalar(), v) || v < range.min ||
        v > range.max) {
      error(key, "element '" + (element.IsScalar() ? element.Scalar() : "?") +
                     "' is invalid; allowed: " + allowed);
      return {};
    }
    parsed.push_back(v);
  }
  value = std::move(parsed);
  return {};
}

ParamDoc ParamReader::read_list(std::string_view key, std::vector<std::string>& value) {
  asked_.emplace_back(key);
  if (describing_) {
    std::string shown;
    for (const std::string& v : value) shown += (shown.empty() ? "" : ", ") + v;
    record({.key = std::string(key), .type = "list<string>", .default_value = "[" + shown + "]"});
    return doc_of(key);
  }
  const YAML::Node& node = impl_->node;
  const YAML::Node item = node.IsMap() ? node[std::string(key)] : YAML::Node();
  if (!item.IsDefined() || item.IsNull()) return {};
  if (!item.IsSequence()) {
    error(key, "wrong shape; allowed: a list of strings");
    return {};
  }
  std::vector<std::string> parsed;
  for (const auto& element : item) {
    if (!element.IsScalar()) {
      error(key, "an element is not a string; allowed: a list of strings");
      return {};
    }
    parsed.push_back(substitute(element.Scalar(), impl_->substitutions));
  }
  value = std::move(parsed);
  return {};
}

void ParamReader::finish() {
  const YAML::Node& node = impl_->node;
  if (!node.IsMap()) return;
  for (const auto& kv : node) {
    const std::string key = kv.first.Scalar();
    if (std::find(asked_.begin(), asked_.end(), key) != asked_.end()) continue;
    std::string known;
    for (const auto& a : asked_) known += (known.empty() ? "" : ", ") + a;
    errors_.push_back(yaml_location(impl_->file, kv.first) + ": " + impl_->path + "." + key +
                      ": unknown parameter; known: " + (known.empty() ? "(none)" : known));
  }
}

}  // namespace scancrew
