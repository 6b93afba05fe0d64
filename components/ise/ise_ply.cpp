#include "components/ise/ise_ply.hpp"

#include <cerrno>
#include <cstdio>
#include <memory>
#include <system_error>

namespace scancrew::ise {

Result<void, std::string> write_ise_ply(const IseResult& r, const std::string& path) {
  const std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "w"), &std::fclose);
  if (!f)
    return make_unexpected("cannot write " + path + ": " +
                           std::error_code(errno, std::generic_category()).message());
  std::fprintf(f.get(),
               "ply\nformat ascii 1.0\ncomment scancrew ISEs (green: inspectable, red: C_rem) "
               "and viewpoints (blue)\nelement vertex %zu\nproperty float x\nproperty float y\n"
               "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
               "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n",
               r.ises.size() + r.viewpoints.size());
  for (size_t i = 0; i < r.ises.size(); ++i) {
    const Ise& e = r.ises[i];
    const bool ok = i < r.inspectable.size() && r.inspectable[i] != 0;
    std::fprintf(f.get(), "%.4f %.4f %.4f %.4f %.4f %.4f %d %d %d\n", e.center.x(), e.center.y(),
                 e.center.z(), e.direction.x(), e.direction.y(), e.direction.z(), ok ? 40 : 220,
                 ok ? 200 : 40, 40);
  }
  for (const Viewpoint& v : r.viewpoints) {
    const Eigen::Vector3d look = v.look();
    std::fprintf(f.get(), "%.4f %.4f %.4f %.4f %.4f %.4f 40 80 230\n", v.position.x(),
                 v.position.y(), v.position.z(), look.x(), look.y(), look.z());
  }
  if (std::ferror(f.get()) != 0) return make_unexpected("write error on " + path);
  return {};
}

}  // namespace scancrew::ise
