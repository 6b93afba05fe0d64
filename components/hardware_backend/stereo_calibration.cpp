// Calibration files -> StereoCalibration, every problem named with file, line and key.

#include "components/hardware_backend/stereo_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "executors/params_impl.hpp"

namespace scancrew::hardware_backend {

namespace {

constexpr double kRotationTolerance = 1e-6;  // |R·Rᵀ - I| and |det R - 1|, numeric noise only

class CalibrationReader {
 public:
  explicit CalibrationReader(std::string label) : label_(std::move(label)) {}

  Result<StereoCalibration, CalibrationErrors> read(const YAML::Node& root) {
    if (!root.IsMap()) {
      errors_.push_back(label_ + ": a calibration file is a mapping (left, right, R, T)");
      return make_unexpected(errors_);
    }
    StereoCalibration c;
    c.source = label_;
    known_keys(root, "", {"left", "right", "R", "T"});
    read_camera(root, "left", c.left);
    read_camera(root, "right", c.right);
    std::vector<double> numbers;
    if (read_numbers(root, "", "R", {9}, "9 numbers, a row-major 3x3 rotation", numbers)) {
      std::copy(numbers.begin(), numbers.end(), c.R_right_left.begin());
      check_rotation(root["R"], c.R_right_left);
    }
    if (read_numbers(root, "", "T", {3}, "3 numbers, the translation in metres", numbers)) {
      std::copy(numbers.begin(), numbers.end(), c.T_right_left_m.begin());
      check_translation(root["T"], c.T_right_left_m);
    }
    if (c.left.width != 0 && c.right.width != 0 &&
        (c.left.width != c.right.width || c.left.height != c.right.height))
      error(root["right"]["image_width"], "right.image_width",
            "the right camera's " + size_text(c.right) + " differs from the left camera's " +
                size_text(c.left) + "; allowed: both cameras calibrated at the same size");
    if (!errors_.empty()) return make_unexpected(errors_);
    return c;
  }

 private:
  static std::string size_text(const CameraCalibration& c) {
    return std::to_string(c.width) + "x" + std::to_string(c.height) + " px";
  }

  void error(const YAML::Node& at, const std::string& path, const std::string& message) {
    errors_.push_back(yaml_location(label_, at) + ": " + path + ": " + message);
  }

  void known_keys(const YAML::Node& map, const std::string& prefix,
                  std::initializer_list<std::string_view> allowed) {
    for (const auto& kv : map) {
      const std::string key = kv.first.Scalar();
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      std::string list;
      for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      error(kv.first, prefix + key, "unknown key; allowed: " + list);
    }
  }

  // A list of finite numbers whose length is one of `sizes`; false (and an error) otherwise.
  bool read_numbers(const YAML::Node& parent, const std::string& prefix, const std::string& key,
                    std::initializer_list<size_t> sizes, const std::string& allowed,
                    std::vector<double>& out, bool required = true) {
    const std::string path = prefix + key;
    const YAML::Node node = parent[key];
    out.clear();
    if (!node.IsDefined() || node.IsNull()) {
      if (required) error(parent, path, "missing; allowed: " + allowed);
      return false;
    }
    if (!node.IsSequence()) {
      error(node, path, "not a list; allowed: " + allowed);
      return false;
    }
    if (std::find(sizes.begin(), sizes.end(), node.size()) == sizes.end()) {
      error(node, path, "has " + std::to_string(node.size()) + " numbers; allowed: " + allowed);
      return false;
    }
    for (size_t i = 0; i < node.size(); ++i) {
      const YAML::Node element = node[i];
      double v = 0;
      bool ok = element.IsScalar();
      if (ok) {
        try {
          v = element.as<double>();
        } catch (const YAML::Exception&) {
          ok = false;
        }
      }
      if (!ok || !std::isfinite(v)) {
        error(element, path,
              "element " + std::to_string(i) + " ('" +
                  (element.IsScalar() ? element.Scalar() : "?") +
                  "') is not a finite number; allowed: " + allowed);
        return false;
      }
      out.push_back(v);
    }
    return true;
  }

  void read_size(const YAML::Node& camera, const std::string& prefix, const std::string& key,
                 uint32_t& out) {
    const std::string path = prefix + key;
    const YAML::Node node = camera[key];
    const std::string allowed = "an integer in [1, 65535], px";
    if (!node.IsDefined() || node.IsNull()) {
      error(camera, path, "missing; allowed: " + allowed);
      return;
    }
    double v = 0;
    bool ok = node.IsScalar();
    if (ok) {
      try {
        v = node.as<double>();
      } catch (const YAML::Exception&) {
        ok = false;
      }
    }
    if (!ok || v != std::floor(v) || v < 1 || v > 65535) {
      error(node, path,
            "'" + (node.IsScalar() ? node.Scalar() : "?") + "' is invalid; allowed: " + allowed);
      return;
    }
    out = static_cast<uint32_t>(v);
  }

  void read_camera(const YAML::Node& root, const std::string& name, CameraCalibration& c) {
    const YAML::Node node = root[name];
    const std::string allowed = "a mapping {image_width, image_height, K, D}";
    if (!node.IsDefined() || node.IsNull()) {
      error(root, name, "missing; allowed: " + allowed);
      return;
    }
    if (!node.IsMap()) {
      error(node, name, "not a mapping; allowed: " + allowed);
      return;
    }
    const std::string prefix = name + ".";
    known_keys(node, prefix, {"image_width", "image_height", "K", "D"});
    read_size(node, prefix, "image_width", c.width);
    read_size(node, prefix, "image_height", c.height);
    std::vector<double> k;
    if (read_numbers(node, prefix, "K", {9}, "9 numbers, row-major [fx 0 cx 0 fy cy 0 0 1], px",
                     k)) {
      std::copy(k.begin(), k.end(), c.K.begin());
      check_camera_matrix(node["K"], prefix + "K", c);
    }
    read_numbers(node, prefix, "D", {0, 4, 5, 8, 12, 14},
                 "0, 4, 5, 8, 12 or 14 numbers (OpenCV: k1 k2 p1 p2 [k3 [k4 k5 k6 [s1..s4 "
                 "[tx ty]]]]); absent = no distortion",
                 c.D, /*required=*/false);
  }

  void check_camera_matrix(const YAML::Node& at, const std::string& path,
                           const CameraCalibration& c) {
    const auto& k = c.K;
    if (!(k[0] > 0 && k[4] > 0) || k[3] != 0 || k[6] != 0 || k[7] != 0 || k[8] != 1) {
      error(at, path,
            "not a camera matrix; allowed: [fx 0 cx 0 fy cy 0 0 1] with fx, fy > 0 (skew in "
            "the second element may be non-zero)");
      return;
    }
    if (c.width != 0 && c.height != 0 &&
        !(k[2] > 0 && k[2] < c.width && k[5] > 0 && k[5] < c.height))
      error(at, path,
            "principal point (" + std::to_string(k[2]) + ", " + std::to_string(k[5]) +
                ") lies outside the " + size_text(c) +
                " image; allowed: cx in (0, width), cy "
                "in (0, height)");
  }

  void check_rotation(const YAML::Node& at, const std::array<double, 9>& r) {
    double worst = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double dot = 0;
        for (int k = 0; k < 3; ++k) dot += r[i * 3 + k] * r[j * 3 + k];
        worst = std::max(worst, std::abs(dot - (i == j ? 1.0 : 0.0)));
      }
    const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                       r[2] * (r[3] * r[7] - r[4] * r[6]);
    if (worst > kRotationTolerance || std::abs(det - 1) > kRotationTolerance)
      error(at, "R",
            "not a rotation (R·Rᵀ differs from I by " + std::to_string(worst) + ", det " +
                std::to_string(det) + "); allowed: an orthonormal 3x3 matrix with det +1");
  }

  void check_translation(const YAML::Node& at, const std::array<double, 3>& t) {
    const double norm = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    if (norm <= 0) {
      error(at, "T", "zero baseline; allowed: the right camera's offset, |T| > 0 m");
      return;
    }
    if (std::abs(t[0]) <= std::abs(t[1])) {
      error(at, "T",
            "a vertical rig (|T.y| >= |T.x|); allowed: a horizontal left/right pair, T mostly "
            "along x");
      return;
    }
    if (t[0] > 0)
      error(at, "T",
            "T.x > 0: the right camera is to the left of the left one; swap left_device and "
            "right_device, or check the convention X_right = R * X_left + T (T.x < 0)");
  }

  std::string label_;
  CalibrationErrors errors_;
};

}  // namespace

double StereoCalibration::baseline_m() const {
  const auto& t = T_right_left_m;
  return std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
}

Result<StereoCalibration, CalibrationErrors> parse_stereo_calibration(const std::string& text,
                                                                      const std::string& label) {
  auto root = parse_yaml(text, label);
  if (!root) return make_unexpected(CalibrationErrors{root.error()});
  return CalibrationReader(label).read(*root);
}

Result<StereoCalibration, CalibrationErrors> load_stereo_calibration(const std::string& path) {
  const auto text = read_text_file(path);
  if (!text)
    return make_unexpected(
        CalibrationErrors{path + ": cannot read the calibration file (" + text.error() + ")"});
  return parse_stereo_calibration(*text, path);
}

}  // namespace scancrew::hardware_backend
