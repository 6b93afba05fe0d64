// Indoor floors for ground robots (docs/scenegen.md, "Indoor"): a walled floor split
// recursively into rooms by walls with doorways and by corridors, a hall with a colonnade
// in front of a covered gallery, then pillars and boxes placed with a clearance.

#include <algorithm>
#include <cmath>

#include "scenegen/draw.hpp"

namespace scancrew::scenegen {

namespace {

constexpr double kWallT = 0.2;         // interior wall thickness, m (halves on the cm grid)
constexpr double kMinRoom = 3.5;       // smallest room side, m
constexpr double kDoorApproach = 1.5;  // kept clear on each side of a doorway, m
constexpr double kClearance = 1.2;     // free-standing objects to anything else, m
constexpr double kWallEndClear = 1.2;  // a wall's end to the nearest doorway edge, m
constexpr double kDoorFromEnd = 0.5;   // a doorway's edge to its wall's end, m

constexpr sim::Rgb kWallColor{0.78, 0.8, 0.82};
constexpr sim::Rgb kPalette[] = {{0.6, 0.6, 0.6},   {0.8, 0.25, 0.2}, {0.85, 0.78, 0.6},
                                 {0.2, 0.2, 0.2},   {0.3, 0.5, 0.75}, {0.55, 0.75, 0.55},
                                 {0.9, 0.65, 0.25}, {0.5, 0.35, 0.25}};

// a coordinate along axis a (0: x, 1: y), and a rectangle from its ranges on a and on the
// other axis
double lo(const Rect& r, int a) {
  return a == 0 ? r.x0 : r.y0;
}
double hi(const Rect& r, int a) {
  return a == 0 ? r.x1 : r.y1;
}
Rect span(int a, double a0, double a1, double b0, double b1) {
  return a == 0 ? Rect{a0, b0, a1, b1} : Rect{b0, a0, b1, a1};
}

// a doorway in a wall across axis a: the wall's centre line at `line` on a, the opening
// [from, to] on the other axis
struct Doorway {
  int axis;
  double line, from, to;
};

class IndoorDrawer {
 public:
  explicit IndoorDrawer(Rng& rng) : rng_(rng) {}

  Candidate draw() {
    // the floor: sides 15-40 m, mostly toward 15-25 m; walls 2-5 m; a ceiling half the time
    const double width = cm(15.0 + 25.0 * std::pow(rng_.unit(), 3.0));
    const double depth = cm(std::clamp(width * rng_.uniform(0.7, 1.3), 15.0, 40.0));
    height_ = std::round(rng_.uniform(2.0, 5.0) * 10.0) / 10.0;
    door_h_ = cm(std::min(rng_.uniform(2.0, 2.4), height_ - 0.3));
    sim::SceneSpec& s = c_.scene;
    s.min_m = {cm(-0.5 * width), cm(-0.5 * depth), 0.0};
    s.max_m = {s.min_m.x + width, s.min_m.y + depth, height_};
    s.wall_height_m = height_;
    s.wall_thickness_m = 0.2;
    s.ceiling = rng_.chance(0.5);
    const Rect floor{s.min_m.x, s.min_m.y, s.max_m.x, s.max_m.y};

    // rooms and corridors, then what stands in the rooms
    split(floor, 0);
    for (size_t i = 0; i < rooms_.size(); ++i)
      if (i == hall_ || (std::min(rooms_[i].width(), rooms_[i].depth()) >= 7.0 && rng_.chance(0.5)))
        gallery(rooms_[i]);
    for (const Rect& room : rooms_) furnish(room);
    return std::move(c_);
  }

 private:
  // splits a region across its longer side by a wall or a corridor, or keeps it as a room;
  // the first split sets a hall apart
  void split(const Rect& r, int level) {
    const int a = r.width() >= r.depth() ? 0 : 1;
    const double extent = hi(r, a) - lo(r, a);
    const double area = r.width() * r.depth();
    if (extent < 2 * kMinRoom + kWallT || (level > 0 && area < rng_.uniform(30.0, 90.0))) {
      rooms_.push_back(r);
      return;
    }
    const bool corridor =
        level <= 2 && extent >= 2 * kMinRoom + 2 * kWallT + 2.4 && level > 0 && rng_.chance(0.35);
    const double corridor_w = corridor ? 2 * cm(rng_.uniform(0.7, 1.2)) : 0.0;  // even cm
    const double band = corridor ? corridor_w + 2 * kWallT : kWallT;  // what the split takes
    double p = 0;
    bool found = false, hall_low = false;
    for (int attempt = 0; attempt < 20 && !found; ++attempt) {
      if (level == 0) {
        // the hall: 7-12 m on one side of the first wall
        const double hall = std::min(rng_.uniform(7.0, 12.0), extent - kMinRoom - band);
        hall_low = rng_.chance(0.5);
        p = hall_low ? lo(r, a) + hall + 0.5 * band : hi(r, a) - hall - 0.5 * band;
      } else {
        p = rng_.uniform(lo(r, a) + kMinRoom + 0.5 * band, hi(r, a) - kMinRoom - 0.5 * band);
      }
      p = cm(p);
      found = corridor ? wall_end_clear(r, a, p - 0.5 * band + 0.5 * kWallT) &&
                             wall_end_clear(r, a, p + 0.5 * band - 0.5 * kWallT)
                       : wall_end_clear(r, a, p);
    }
    if (!found) {
      rooms_.push_back(r);
      return;
    }
    const double b0 = lo(r, 1 - a), b1 = hi(r, 1 - a);
    const Rect low = span(a, lo(r, a), p - 0.5 * band, b0, b1);
    const Rect high = span(a, p + 0.5 * band, hi(r, a), b0, b1);
    if (corridor) {
      wall(a, p - 0.5 * band + 0.5 * kWallT, b0, b1);
      wall(a, p + 0.5 * band - 0.5 * kWallT, b0, b1);
      const Rect way = span(a, p - 0.5 * corridor_w, p + 0.5 * corridor_w, b0, b1);
      c_.passages.push_back({Passage::Kind::kCorridor, "corridor_" + std::to_string(++corridors_),
                             way, corridor_w, height_});
      c_.layout.add_keep_out(way);
    } else {
      wall(a, p, b0, b1);
    }
    if (level == 0) {
      // the hall is kept whole
      hall_ = rooms_.size();
      rooms_.push_back(hall_low ? low : high);
      split(hall_low ? high : low, 1);
      return;
    }
    split(low, level + 1);
    split(high, level + 1);
  }

  // a wall across axis a at `line` may end on the region's sides only away from their
  // doorways
  bool wall_end_clear(const Rect& r, int a, double line) const {
    const int b = 1 - a;
    for (const Doorway& d : doors_) {
      if (d.axis != b) continue;
      if (std::abs(d.line - lo(r, b)) > kWallT && std::abs(d.line - hi(r, b)) > kWallT) continue;
      if (line + 0.5 * kWallT + kWallEndClear > d.from &&
          line - 0.5 * kWallT - kWallEndClear < d.to)
        return false;
    }
    return true;
  }

  // a wall across axis a, centred on `line`, from b0 to b1 on the other axis, with one
  // doorway per 10 m started (each 1.2-2.0 m wide, a lintel above it)
  void wall(int a, double line, double b0, double b1) {
    const int id = ++walls_;
    const int n = 1 + static_cast<int>((b1 - b0) / 10.0);
    const double segment = (b1 - b0) / n;
    double from = b0;
    for (int k = 0; k < n; ++k) {
      const double w = cm(rng_.uniform(1.2, 2.0));
      const double s0 = b0 + k * segment + kDoorFromEnd, s1 = b0 + (k + 1) * segment - kDoorFromEnd;
      const double d0 = cm(rng_.uniform(s0, std::max(s0, s1 - w)));
      const Doorway door{a, line, d0, d0 + w};
      doors_.push_back(door);
      const std::string name = "wall_" + std::to_string(id) + "_" + std::to_string(k + 1);
      solid(make_box(name, span(a, line - 0.5 * kWallT, line + 0.5 * kWallT, from, door.from), 0,
                     height_, kWallColor));
      c_.scene.boxes.push_back(
          make_box("lintel_" + std::to_string(id) + "_" + std::to_string(k + 1),
                   span(a, line - 0.5 * kWallT, line + 0.5 * kWallT, door.from, door.to), door_h_,
                   height_, kWallColor));
      c_.passages.push_back({Passage::Kind::kDoorway, name,
                             span(a, line - 0.5 * kWallT, line + 0.5 * kWallT, door.from, door.to),
                             w, door_h_});
      c_.layout.add_keep_out(span(a, line - 0.5 * kWallT - kDoorApproach,
                                  line + 0.5 * kWallT + kDoorApproach, door.from - 0.3,
                                  door.to + 0.3));
      from = door.to;
    }
    solid(make_box("wall_" + std::to_string(id) + "_" + std::to_string(n + 1),
                   span(a, line - 0.5 * kWallT, line + 0.5 * kWallT, from, b1), 0, height_,
                   kWallColor));
  }

  // a covered gallery along one long side of a room: a roof slab 1.7-3 m up, carried on
  // the wall and on a row of columns 2.5-4 m apart at the gallery's front edge
  void gallery(const Rect& room) {
    const int a = room.width() <= room.depth() ? 0 : 1;  // the gallery's depth runs along a
    const bool at_low = rng_.chance(0.5);
    const double g = cm(rng_.uniform(2.0, 3.2));
    const double r = cm(rng_.uniform(0.18, 0.3));
    const double pitch = rng_.uniform(2.5, 4.0);
    const double roof_b = cm(std::min(rng_.uniform(2.2, 3.0), height_ - 0.35));
    const double roof_t = roof_b + cm(rng_.uniform(0.15, 0.25));
    const double b0 = lo(room, 1 - a), b1 = hi(room, 1 - a), length = b1 - b0;
    // the column line, and the gallery from the wall to it
    const double front = at_low ? lo(room, a) + g : hi(room, a) - g;
    const double wall_side = at_low ? lo(room, a) : hi(room, a);
    const double roof_edge = at_low ? front + r : front - r;
    const int id = ++galleries_;
    const std::string tag = "gallery_" + std::to_string(id);
    c_.scene.boxes.push_back(
        make_box(tag + "_roof",
                 span(a, std::min(wall_side, roof_edge), std::max(wall_side, roof_edge), b0, b1),
                 roof_b, roof_t, kPalette[2]));
    const double inner = at_low ? front - r : front + r;
    const Rect under = span(a, std::min(wall_side, inner), std::max(wall_side, inner), b0, b1);
    c_.passages.push_back({Passage::Kind::kGallery, tag, under, g - r, roof_b});
    c_.layout.add_keep_out(under);
    // columns: end gaps of at least 1.8 m, evenly spaced
    const int n = 1 + static_cast<int>(std::max(0.0, length - 3.6) / pitch);
    const double end = 0.5 * (length - (n - 1) * pitch);
    double previous = b0;
    for (int k = 0; k < n; ++k) {
      const double b = cm(b0 + end + k * pitch);
      sim::CylinderSpec col;
      col.name = tag + "_column_" + std::to_string(k + 1);
      col.center_m = a == 0 ? msg::Vec3{front, b, 0.5 * roof_b} : msg::Vec3{b, front, 0.5 * roof_b};
      col.radius_m = r;
      col.height_m = roof_b;
      col.color = kPalette[0];
      c_.layout.add_solid(footprint(col));
      c_.scene.cylinders.push_back(col);
      if (k > 0)
        c_.passages.push_back({Passage::Kind::kColonnadeGap, col.name,
                               span(a, front - r, front + r, previous + r, b - r),
                               b - previous - 2 * r, roof_b});
      previous = b;
    }
    c_.layout.add_keep_out(span(a, front - r, front + r, b0, b1));
  }

  // pillars and boxes of assorted sizes, each at least kClearance from anything else
  void furnish(const Rect& room) {
    const int wanted = static_cast<int>(room.width() * room.depth() / rng_.uniform(8.0, 16.0));
    for (int i = 0; i < wanted; ++i) {
      for (int attempt = 0; attempt < 12; ++attempt) {
        const double x = cm(rng_.uniform(room.x0, room.x1));
        const double y = cm(rng_.uniform(room.y0, room.y1));
        const double kind = rng_.unit();
        const sim::Rgb color = kPalette[rng_.integer(0, 7)];
        if (kind < 0.2) {
          sim::CylinderSpec p;
          p.name = "pillar_" + std::to_string(++objects_);
          p.radius_m = cm(rng_.uniform(0.15, 0.35));
          p.height_m = height_;
          p.center_m = {x, y, 0.5 * height_};
          p.color = color;
          if (place(footprint(p), room, p.name)) {
            c_.scene.cylinders.push_back(p);
            break;
          }
          --objects_;
          continue;
        }
        sim::BoxSpec b;
        if (kind < 0.35) {
          const double side = cm(rng_.uniform(0.3, 0.6));
          b.name = "pillar_" + std::to_string(++objects_);
          b.size_m = {side, side, height_};
          b.yaw_rad = rng_.chance(0.5) ? 0.0 : M_PI / 4;
        } else {
          b.name = "box_" + std::to_string(++objects_);
          b.size_m = {cm(0.3 + 1.9 * std::pow(rng_.unit(), 1.5)),
                      cm(0.3 + 1.9 * std::pow(rng_.unit(), 1.5)),
                      cm(rng_.uniform(0.3, std::min(2.0, height_)))};
          b.yaw_rad = rng_.integer(0, 179) * M_PI / 180.0;
        }
        b.center_m = {x, y, 0.5 * b.size_m.z};
        b.color = color;
        if (place(footprint(b), room, b.name)) {
          c_.scene.boxes.push_back(b);
          break;
        }
        --objects_;
      }
    }
  }

  bool place(const Rect& fp, const Rect& room, const std::string& name) {
    if (!c_.layout.fits(fp, room, kClearance)) return false;
    c_.layout.add_solid(fp);
    c_.removable.push_back({name});
    return true;
  }

  void solid(sim::BoxSpec box) {
    if (box.size_m.x <= 1e-6 || box.size_m.y <= 1e-6) return;  // a doorway at a wall's end
    c_.layout.add_solid(footprint(box));
    c_.scene.boxes.push_back(std::move(box));
  }

  Rng& rng_;
  Candidate c_;
  double height_ = 0, door_h_ = 0;
  std::vector<Doorway> doors_;
  std::vector<Rect> rooms_;
  size_t hall_ = 0;
  int walls_ = 0, corridors_ = 0, galleries_ = 0, objects_ = 0;
};

}  // namespace

Candidate draw_indoor(Rng& rng) {
  return IndoorDrawer(rng).draw();
}

}  // namespace scancrew::scenegen
