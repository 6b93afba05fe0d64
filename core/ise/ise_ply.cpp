#include "core/ise/ise_ply.hpp"

#include <array>
#include <vector>

#include "core/io/ply.hpp"

namespace scancrew::ise {

Result<void, std::string> write_ise_ply(const IseResult& r, const std::string& path) {
  std::vector<std::array<float, 3>> points, normals;
  std::vector<std::array<uint8_t, 3>> colours;
  const size_t n = r.ises.size() + r.viewpoints.size();
  points.reserve(n);
  normals.reserve(n);
  colours.reserve(n);
  const auto add = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& d,
                       std::array<uint8_t, 3> rgb) {
    points.push_back(
        {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
    normals.push_back(
        {static_cast<float>(d.x()), static_cast<float>(d.y()), static_cast<float>(d.z())});
    colours.push_back(rgb);
  };
  for (size_t i = 0; i < r.ises.size(); ++i) {
    const bool ok = i < r.inspectable.size() && r.inspectable[i] != 0;
    add(r.ises[i].center, r.ises[i].direction,
        ok ? std::array<uint8_t, 3>{40, 200, 40} : std::array<uint8_t, 3>{220, 40, 40});
  }
  for (const Viewpoint& v : r.viewpoints) add(v.position, v.look(), {40, 80, 230});
  return io::write_ply(
      path, {.positions = io::flat(points),
             .normals = io::flat(normals),
             .colours = io::flat(colours),
             .comments = {"scancrew ISEs (green: inspectable, red: C_rem) and viewpoints (blue)"}});
}

}  // namespace scancrew::ise
