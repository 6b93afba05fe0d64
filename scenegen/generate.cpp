// generate(): draw, choose starts, check the free space, repair or redraw (docs/scenegen.md,
// "What is guaranteed").

#include <algorithm>
#include <limits>

#include "eval/free_space.hpp"
#include "scenegen/draw.hpp"
#include "sim/scene_solids.hpp"

namespace scancrew::scenegen {

namespace {

constexpr int kMaxDraws = 6;    // candidates per seed before giving up
constexpr int kMaxRepairs = 8;  // repairs per candidate before drawing again
constexpr size_t kStarts = 6;   // starts listed (at least 5 are required)
constexpr size_t kMinStarts = 5;

struct StartRule {
  double clearance_m, z_m;
};
StartRule start_rule(Family f) {
  // a ground robot's body fits in a 0.3 m disc: 0.9 m leaves room to turn and to pass;
  // a multirotor's 1 m sphere at 2 m up, 2.5 m from any footprint
  return f == Family::kIndoor ? StartRule{0.9, 0.0} : StartRule{2.5, 2.0};
}

std::vector<sim::StartPose>& starts_of(sim::SceneSpec& s, Family f) {
  return f == Family::kIndoor ? s.starts.ground : s.starts.multirotor;
}

// the free-space check, and one free cell no start reaches (for the repair)
struct Check {
  FreeSpaceCheck summary;
  std::vector<size_t> blocked_starts;
  std::optional<msg::Vec3> stranded;
};

Result<Check, std::string> check(const sim::SceneSpec& scene, Family family) {
  const sim::SceneSolids solids(scene, {});
  const eval::FreeSpaceBody body = eval::default_body(robot_kind(family));
  std::vector<msg::Vec3> points;
  for (const auto& p : family == Family::kIndoor ? scene.starts.ground : scene.starts.multirotor)
    points.push_back(p.position_m);
  auto space = eval::FreeSpace::build(solids, scene, body, points);
  if (!space) return make_unexpected("the free-space check refused the scene: " + space.error());
  Check c;
  c.summary.connected = space->connected();
  c.summary.free_cells = space->free_cells();
  c.summary.reachable_cells = space->reachable_cells();
  for (size_t i = 0; i < points.size(); ++i)
    if (!space->start_free(i)) c.blocked_starts.push_back(i);
  c.summary.starts_free = c.blocked_starts.empty();
  if (!c.summary.connected) {
    // a free place no start reaches: on a lattice of cells, where the body fits but the
    // flood did not come
    const double step = space->cell_m();
    const double z0 = family == Family::kIndoor ? 0.0 : body.min_altitude_m;
    const double z1 =
        family == Family::kIndoor ? 0.0 : std::min(body.max_altitude_m, scene.max_m.z);
    for (double z = z0; z <= z1 && !c.stranded; z += family == Family::kIndoor ? 1.0 : step)
      for (double x = scene.min_m.x + 0.5 * step; x < scene.max_m.x && !c.stranded; x += step)
        for (double y = scene.min_m.y + 0.5 * step; y < scene.max_m.y && !c.stranded; y += step) {
          const msg::Vec3 p{x, y, z};
          const bool fits =
              family == Family::kIndoor
                  ? !solids.cylinder_overlaps(x, y, body.radius_m, body.clearance_m, body.height_m)
                  : !solids.sphere_overlaps(p, body.radius_m);
          if (fits && !space->reachable(p)) c.stranded = p;
        }
  }
  return c;
}

// drops the removable object nearest to p from the scene and the candidate's list
bool drop_nearest(Candidate& c, const std::optional<msg::Vec3>& p) {
  if (c.removable.empty()) return false;
  size_t pick = c.removable.size() - 1;
  const auto fp = [&](const std::string& name) -> std::optional<Rect> {
    for (const auto& b : c.scene.boxes)
      if (b.name == name) return footprint(b);
    for (const auto& y : c.scene.cylinders)
      if (y.name == name) return footprint(y);
    return std::nullopt;
  };
  if (p) {
    double best = std::numeric_limits<double>::max();
    const Rect at{p->x, p->y, p->x, p->y};
    for (size_t i = 0; i < c.removable.size(); ++i)
      for (const auto& name : c.removable[i])
        if (auto r = fp(name); r && gap(*r, at) < best) {
          best = gap(*r, at);
          pick = i;
        }
  }
  const auto& names = c.removable[pick];
  const auto named = [&](const auto& o) {
    return std::find(names.begin(), names.end(), o.name) != names.end();
  };
  std::erase_if(c.scene.boxes, named);
  std::erase_if(c.scene.cylinders, named);
  c.removable.erase(c.removable.begin() + static_cast<std::ptrdiff_t>(pick));
  return true;
}

}  // namespace

Result<GeneratedScene, std::string> generate(Family family, uint64_t seed) {
  Rng rng(seed);
  const StartRule rule = start_rule(family);
  std::string why;
  for (int draw = 1; draw <= kMaxDraws; ++draw) {
    Candidate c = family == Family::kIndoor ? draw_indoor(rng) : draw_outdoor(rng);
    if (!c.defect.empty()) {
      why = c.defect;
      continue;
    }
    c.scene.name = to_string(family) + "_" + std::to_string(seed);
    c.scene.texture_seed = seed;
    std::vector<sim::StartPose> skipped;
    int repairs = 0;
    for (; repairs <= kMaxRepairs; ++repairs) {
      auto& starts = starts_of(c.scene, family);
      starts = choose_starts(c, rng, kStarts, rule.clearance_m, rule.z_m, skipped);
      if (starts.size() < kMinStarts) {
        why = "only " + std::to_string(starts.size()) + " free start places";
        break;
      }
      auto result = check(c.scene, family);
      if (!result)
        return make_unexpected(to_string(family) + " seed " + std::to_string(seed) + ": " +
                               result.error());
      if (result->summary.connected && result->summary.starts_free)
        return GeneratedScene{std::move(c.scene), family, seed,   std::move(c.passages),
                              result->summary,    draw,   repairs};
      // a start that is not free is replaced; a free place no start reaches loses the
      // object nearest to it
      for (size_t i : result->blocked_starts) skipped.push_back(starts[i]);
      why = !result->summary.starts_free
                ? std::to_string(result->blocked_starts.size()) + " start(s) not free"
                : "the free space is not connected";
      if (result->summary.starts_free && !drop_nearest(c, result->stranded)) break;
    }
  }
  return make_unexpected(to_string(family) + " seed " + std::to_string(seed) + ": no scene of " +
                         std::to_string(kMaxDraws) +
                         " draws passed the free-space check (last: " + why + ")");
}

}  // namespace scancrew::scenegen
