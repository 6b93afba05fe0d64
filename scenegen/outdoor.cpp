// Outdoor sites for multirotors (docs/scenegen.md, "Outdoor"): buildings of varied
// footprints and heights, some with an overhang, then pipe racks and towers, each kept a
// multirotor's passage away from the others and from the site's edge. No walls, no ceiling.

#include <algorithm>
#include <cmath>

#include "scenegen/draw.hpp"

namespace scancrew::scenegen {

namespace {

constexpr double kEdge = 3.0;  // the site's edge to any footprint, m
constexpr double kGap = 4.0;   // between footprints: two 1 m collision spheres and a margin, m

constexpr sim::Rgb kFacades[] = {{0.75, 0.72, 0.68}, {0.62, 0.55, 0.5}, {0.8, 0.78, 0.7},
                                 {0.55, 0.6, 0.65},  {0.7, 0.6, 0.45},  {0.5, 0.5, 0.55}};
constexpr sim::Rgb kSteel{0.45, 0.47, 0.5};
constexpr sim::Rgb kPipe{0.7, 0.55, 0.3};
constexpr sim::Rgb kConcrete{0.68, 0.68, 0.66};

Rect around(const Rect& a, const Rect& b) {
  return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

Rect centred(double x, double y, double sx, double sy) {
  return {cm(x - 0.5 * sx), cm(y - 0.5 * sy), cm(x - 0.5 * sx) + cm(sx), cm(y - 0.5 * sy) + cm(sy)};
}

// one object being drawn: its pieces and the rectangle around their footprints
struct Group {
  std::vector<sim::BoxSpec> boxes;
  std::vector<sim::CylinderSpec> cylinders;
  Rect extent;
  bool empty = true;

  void add(sim::BoxSpec b) {
    grow(footprint(b));
    boxes.push_back(std::move(b));
  }
  void add(sim::CylinderSpec c) {
    grow(footprint(c));
    cylinders.push_back(std::move(c));
  }
  void move(double dx, double dy) {
    for (auto& b : boxes) b.center_m = {b.center_m.x + dx, b.center_m.y + dy, b.center_m.z};
    for (auto& c : cylinders) c.center_m = {c.center_m.x + dx, c.center_m.y + dy, c.center_m.z};
    extent = {extent.x0 + dx, extent.y0 + dy, extent.x1 + dx, extent.y1 + dy};
  }
  void grow(const Rect& r) {
    extent = empty ? r : around(extent, r);
    empty = false;
  }
};

// Each object is drawn around the origin, then moved to a drawn place where it fits.
class OutdoorDrawer {
 public:
  explicit OutdoorDrawer(Rng& rng) : rng_(rng) {}

  Candidate draw() {
    // the site: 40-80 m a side, mostly toward 40-60 m
    const double width = cm(40.0 + 40.0 * rng_.unit() * rng_.unit());
    const double depth = cm(std::clamp(width * rng_.uniform(0.75, 1.33), 40.0, 80.0));
    sim::SceneSpec& s = c_.scene;
    s.min_m = {cm(-0.5 * width), cm(-0.5 * depth), 0.0};
    s.max_m = {s.min_m.x + width, s.min_m.y + depth, 10.0};
    s.dot_size_m = 0.05;
    site_ = Rect{s.min_m.x, s.min_m.y, s.max_m.x, s.max_m.y};

    // a pipe rack and a tower first (they are long or wide: they fit best on an empty site),
    // then 3-8 buildings, at most one per 400 m2 of site so that a small site is not crowded,
    // then up to one more rack and two more towers where room is left; a site where fewer
    // than 3 buildings, the first rack or the first tower fit is drawn again
    const int buildings =
        rng_.integer(3, std::clamp(static_cast<int>(width * depth / 400.0), 3, 8));
    const int racks = rng_.integer(1, 2), towers = rng_.integer(1, 3);
    // building sides up to 18 m, less where many share a small site
    max_side_ = std::clamp(0.5 * std::sqrt(width * depth / buildings), 8.0, 18.0);
    max_rack_m_ = std::min(22.0, 0.4 * std::min(width, depth));
    int racks_placed = place([&] { return pipe_rack(1); }, true);
    int towers_placed = place([&] { return tower(1); }, true);
    if (racks_placed == 0 || towers_placed == 0) c_.defect = "no room for a pipe rack or a tower";
    int placed = 0;
    for (int i = 1; i <= buildings; ++i)
      placed += place([&] { return building(placed + 1); }, false);
    if (placed < 3) c_.defect = "only " + std::to_string(placed) + " buildings fit on the site";
    for (int i = 2; i <= racks; ++i)
      racks_placed += place([&] { return pipe_rack(racks_placed + 1); }, true);
    for (int i = 2; i <= towers; ++i)
      towers_placed += place([&] { return tower(towers_placed + 1); }, true);

    // the region to reconstruct: 2 m above the tallest top
    double top = 0;
    for (const auto& b : s.boxes) top = std::max(top, b.center_m.z + 0.5 * b.size_m.z);
    for (const auto& c : s.cylinders) top = std::max(top, c.center_m.z + 0.5 * c.height_m);
    s.max_m.z = std::max(10.0, std::ceil(top + 2.0));
    return std::move(c_);
  }

 private:
  // draws the object up to 60 times until its footprint fits
  template <class Draw>
  bool place(Draw&& draw, bool removable) {
    const Rect inside = site_.grown(-kEdge);
    for (int attempt = 0; attempt < 60; ++attempt) {
      Group g = draw();
      // drawn around the origin; moved to a place drawn where it stays inside the site
      const double x0 = inside.x0 - g.extent.x0, x1 = inside.x1 - g.extent.x1;
      const double y0 = inside.y0 - g.extent.y0, y1 = inside.y1 - g.extent.y1;
      if (x0 > x1 || y0 > y1) continue;
      g.move(cm(rng_.uniform(x0, x1)), cm(rng_.uniform(y0, y1)));
      if (!c_.layout.fits(g.extent, site_.grown(kGap - kEdge), kGap)) continue;  // kEdge in
      std::vector<std::string> names;
      for (auto& b : g.boxes) {
        names.push_back(b.name);
        c_.scene.boxes.push_back(std::move(b));
      }
      for (auto& c : g.cylinders) {
        names.push_back(c.name);
        c_.scene.cylinders.push_back(std::move(c));
      }
      c_.layout.add_solid(g.extent);
      if (removable) c_.removable.push_back(std::move(names));
      return true;
    }
    return false;
  }

  static double height(double h) { return std::round(h * 10.0) / 10.0; }

  // a rectangular block, an L (a wing on one side) or a stepped block (a tower on part of a
  // low base); sides 6 m to max_side_ (8-18 m), 4-20 m tall; half of those 6 m or taller
  // carry an overhang
  Group building(int id) {
    Group g;
    const std::string tag = "building_" + std::to_string(id);
    const sim::Rgb color = kFacades[rng_.integer(0, 5)];
    const double sx = rng_.uniform(6.0, max_side_), sy = rng_.uniform(6.0, max_side_);
    const double shape = rng_.unit();
    double h = height(rng_.uniform(4.0, 20.0));
    const Rect main = centred(0, 0, sx, sy);
    if (shape < 0.35) {
      // stepped: a base 4-8 m tall, a tower of 40-70 % of it in one corner, 3 m taller or more
      const double base_h = height(rng_.uniform(4.0, 8.0));
      h = std::max(h, base_h + 3.0);
      g.add(make_box(tag + "_base", main, 0, base_h, color));
      const double tx = cm(sx * rng_.uniform(0.4, 0.7)), ty = cm(sy * rng_.uniform(0.4, 0.7));
      const double x0 = rng_.chance(0.5) ? main.x0 : main.x1 - tx;
      const double y0 = rng_.chance(0.5) ? main.y0 : main.y1 - ty;
      g.add(make_box(tag + "_tower", {x0, y0, x0 + tx, y0 + ty}, base_h, h, color));
    } else {
      g.add(make_box(tag, main, 0, h, color));
      if (shape < 0.7) {
        // L: a wing 4-10 m deep (at most 0.6 max_side_) along one side, from one end, 4 m
        // tall or more
        const bool along_x = rng_.chance(0.5);
        const double deep = cm(rng_.uniform(4.0, std::min(10.0, 0.6 * max_side_)));
        const double wing_h = height(rng_.uniform(4.0, h));
        Rect wing;
        if (along_x) {
          const double len = cm(sx * rng_.uniform(0.4, 0.8));
          const double x0 = rng_.chance(0.5) ? main.x0 : main.x1 - len;
          wing = rng_.chance(0.5) ? Rect{x0, main.y1, x0 + len, main.y1 + deep}
                                  : Rect{x0, main.y0 - deep, x0 + len, main.y0};
        } else {
          const double len = cm(sy * rng_.uniform(0.4, 0.8));
          const double y0 = rng_.chance(0.5) ? main.y0 : main.y1 - len;
          wing = rng_.chance(0.5) ? Rect{main.x1, y0, main.x1 + deep, y0 + len}
                                  : Rect{main.x0 - deep, y0, main.x0, y0 + len};
        }
        g.add(make_box(tag + "_wing", wing, 0, wing_h, color));
      }
    }
    const double main_h = g.boxes.front().center_m.z + 0.5 * g.boxes.front().size_m.z;
    if (main_h >= 6.0 && rng_.chance(0.5)) {
      // an overhang: a slab 0.3-0.5 m thick, 2-4 m out from one side of the main block, over
      // 40-80 % of that side, its underside 3 m up or higher
      const double out = cm(rng_.uniform(2.0, 4.0)), thick = cm(rng_.uniform(0.3, 0.5));
      const double under = height(rng_.uniform(3.0, main_h - 1.5));
      const int side = rng_.integer(0, 3);
      const double frac = rng_.uniform(0.4, 0.8);
      Rect slab;
      if (side < 2) {
        const double len = cm(sx * frac), x0 = cm(-0.5 * len);
        slab = side == 0 ? Rect{x0, main.y1, x0 + len, main.y1 + out}
                         : Rect{x0, main.y0 - out, x0 + len, main.y0};
      } else {
        const double len = cm(sy * frac), y0 = cm(-0.5 * len);
        slab = side == 2 ? Rect{main.x1, y0, main.x1 + out, y0 + len}
                         : Rect{main.x0 - out, y0, main.x0, y0 + len};
      }
      g.add(make_box(tag + "_overhang", slab, under, under + thick, kConcrete));
    }
    return g;
  }

  // two rows of posts 5-6 m apart, 10-22 m long (at most 0.4 of the site's shorter side), 2-3 m
  // wide, 4-7 m tall; cross beams at the top (and half the time a lower tier 2 m down) carrying 2-4
  // pipes along the rack
  Group pipe_rack(int id) {
    Group g;
    const std::string tag = "rack_" + std::to_string(id);
    const bool along_x = rng_.chance(0.5);
    const double len = cm(rng_.uniform(10.0, max_rack_m_)), wide = 2 * cm(rng_.uniform(1.0, 1.5));
    const double top = height(rng_.uniform(4.0, 7.0));
    const int bays = std::max(2, static_cast<int>(std::round(len / rng_.uniform(5.0, 6.0))));
    const bool lower = top >= 5.0 && rng_.chance(0.5);
    const int pipes = rng_.integer(2, 4);
    // a rectangle in the rack's frame (u along, v across), to the site's
    const auto to_site = [&](double u0, double u1, double v0, double v1) {
      return along_x ? Rect{cm(u0), cm(v0), cm(u1), cm(v1)} : Rect{cm(v0), cm(u0), cm(v1), cm(u1)};
    };
    const double post = 0.3, beam = 0.25;
    for (int k = 0; k <= bays; ++k) {
      const double u = cm(-0.5 * len + k * len / bays);
      for (int side = 0; side < 2; ++side) {
        const double v = side == 0 ? -0.5 * wide : 0.5 * wide;
        g.add(make_box(tag + "_post_" + std::to_string(k + 1) + "_" + std::to_string(side + 1),
                       to_site(u - 0.5 * post, u + 0.5 * post, v - 0.5 * post, v + 0.5 * post), 0,
                       top, kSteel));
      }
      for (int tier = 0; tier < (lower ? 2 : 1); ++tier) {
        const double z = top - 2.0 * tier;
        g.add(make_box(tag + "_beam_" + std::to_string(k + 1) + "_" + std::to_string(tier + 1),
                       to_site(u - 0.5 * post, u + 0.5 * post, -0.5 * wide - 0.5 * post,
                               0.5 * wide + 0.5 * post),
                       z, z + beam, kSteel));
      }
    }
    for (int tier = 0; tier < (lower ? 2 : 1); ++tier) {
      const double z = top - 2.0 * tier + beam;
      for (int p = 0; p < pipes; ++p) {
        const double d = 2 * cm(rng_.uniform(0.125, 0.25));
        const double v = cm(-0.5 * wide + (p + 1) * wide / (pipes + 1));
        g.add(make_box(tag + "_pipe_" + std::to_string(tier + 1) + "_" + std::to_string(p + 1),
                       to_site(-0.5 * len - 0.5, 0.5 * len + 0.5, v - 0.5 * d, v + 0.5 * d), z,
                       z + d, kPipe));
      }
    }
    return g;
  }

  // a stack (narrow, 12-20 m), a silo (wide, 8-15 m) or a water tower (four legs 8-14 m, 4-6 m
  // apart, and a tank on them)
  Group tower(int id) {
    Group g;
    const std::string tag = "tower_" + std::to_string(id);
    const double kind = rng_.unit();
    sim::CylinderSpec body;
    body.color = kConcrete;
    if (kind < 0.67) {
      const bool stack = kind < 0.33;
      body.name = tag;
      body.radius_m = cm(stack ? rng_.uniform(0.6, 1.5) : rng_.uniform(2.0, 3.5));
      body.height_m = height(stack ? rng_.uniform(12.0, 20.0) : rng_.uniform(8.0, 15.0));
      body.center_m = {0, 0, 0.5 * body.height_m};
      g.add(body);
      return g;
    }
    const double half = cm(rng_.uniform(2.0, 3.0)), legs = height(rng_.uniform(8.0, 14.0));
    for (int k = 0; k < 4; ++k) {
      const double x = k % 2 == 0 ? -half : half, y = k < 2 ? -half : half;
      g.add(make_box(tag + "_leg_" + std::to_string(k + 1), centred(x, y, 0.4, 0.4), 0, legs,
                     kSteel));
    }
    body.name = tag + "_tank";
    body.radius_m = cm(half + 0.5);
    body.height_m = height(rng_.uniform(3.0, 5.0));
    body.center_m = {0, 0, legs + 0.5 * body.height_m};
    g.add(body);
    return g;
  }

  Rng& rng_;
  Candidate c_;
  Rect site_;
  double max_side_ = 18.0, max_rack_m_ = 22.0;
};

}  // namespace

Candidate draw_outdoor(Rng& rng) {
  return OutdoorDrawer(rng).draw();
}

}  // namespace scancrew::scenegen
