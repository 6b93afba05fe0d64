#include "cli/build_info.hpp"

#include <fastcdr/config.h>
#include <fastrtps/config.h>
#include <mujoco/mujoco.h>
#include <ompl/config.h>
#include <oneapi/tbb/version.h>
#include <openssl/opensslv.h>
#include <zstd.h>

#include <CLI/Version.hpp>
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <opencv2/core/version.hpp>

#include "cli/git_commit.hpp"  // generated: SCANCREW_GIT_COMMIT

// from cli/CMakeLists.txt: SCANCREW_VERSION, and the CMake versions of the libraries whose
// headers say none (SCANCREW_YAML_CPP_VERSION, SCANCREW_OCTOMAP_VERSION)

namespace scancrew::cli {

namespace {

std::string dotted(int major, int minor, int patch) {
  return std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(patch);
}

}  // namespace

std::string scancrew_version() {
  return SCANCREW_VERSION;
}

std::string git_commit() {
  return SCANCREW_GIT_COMMIT;
}

std::vector<Dependency> dependency_versions() {
  // mjVERSION_HEADER: 222 for 2.2.2, 312 for 3.1.2
  const std::string mujoco =
      dotted(mjVERSION_HEADER / 100, mjVERSION_HEADER / 10 % 10, mjVERSION_HEADER % 10);
  return {
      {"MuJoCo", mujoco},
      {"Fast DDS", FASTRTPS_VERSION_STR},
      {"Fast CDR", dotted(FASTCDR_VERSION_MAJOR, FASTCDR_VERSION_MINOR, FASTCDR_VERSION_MICRO)},
      {"OpenCV", CV_VERSION},
      {"Eigen", dotted(EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION)},
      {"yaml-cpp", SCANCREW_YAML_CPP_VERSION},
      {"oneTBB", TBB_VERSION_STRING},
      {"OctoMap", SCANCREW_OCTOMAP_VERSION},
      {"OMPL", dotted(OMPL_MAJOR_VERSION, OMPL_MINOR_VERSION, OMPL_PATCH_VERSION)},
      {"zstd", ZSTD_VERSION_STRING},
      {"OpenSSL", OPENSSL_VERSION_STR},
      {"nlohmann_json", dotted(NLOHMANN_JSON_VERSION_MAJOR, NLOHMANN_JSON_VERSION_MINOR,
                               NLOHMANN_JSON_VERSION_PATCH)},
      {"CLI11", CLI11_VERSION},
  };
}

std::string version_text() {
  std::string text = "scancrew " + scancrew_version() + " (commit " + git_commit() + ")\n";
  text += "built with:\n";
  for (const Dependency& d : dependency_versions()) text += "  " + d.name + " " + d.version + "\n";
  text.pop_back();  // CLI11 ends the version text with a newline of its own
  return text;
}

}  // namespace scancrew::cli
