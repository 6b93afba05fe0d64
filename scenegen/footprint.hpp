#pragma once

// Footprints on the floor (x-y, axis aligned) and the clearance rule the generators keep:
// a free-standing object is placed only where its footprint is at least a clearance away
// from every other footprint and outside every keep-out area (doorway approaches,
// galleries, corridors). Plain value types; nothing here allocates but the Layout's lists.

#include <string>
#include <vector>

#include "sim/scene.hpp"

namespace scancrew::scenegen {

struct Rect {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // min and max corners, m

  double width() const { return x1 - x0; }
  double depth() const { return y1 - y0; }
  Rect grown(double margin_m) const {
    return {x0 - margin_m, y0 - margin_m, x1 + margin_m, y1 + margin_m};
  }
};

// Euclidean distance between two rectangles; 0 when they touch or overlap.
double gap(const Rect& a, const Rect& b);
bool overlaps(const Rect& a, const Rect& b);  // interiors intersect

// The axis-aligned rectangle around a (yawed) box's or a cylinder's footprint.
Rect footprint(const sim::BoxSpec& box);
Rect footprint(const sim::CylinderSpec& cylinder);

// A box standing on the floor or floating, from its footprint and z range.
sim::BoxSpec make_box(std::string name, const Rect& r, double z0_m, double z1_m, sim::Rgb color);

// What the generator has placed so far, as footprints, and where nothing may go.
class Layout {
 public:
  void add_solid(const Rect& r) { solids_.push_back(r); }
  void add_keep_out(const Rect& r) { keep_out_.push_back(r); }
  // true when r is inside `inside` (shrunk by clearance_m), at least clearance_m from every
  // solid and overlaps no keep-out area
  bool fits(const Rect& r, const Rect& inside, double clearance_m) const;
  // distance from a point to the nearest solid footprint (a large number when none)
  double clearance_at(double x_m, double y_m) const;

 private:
  std::vector<Rect> solids_, keep_out_;
};

}  // namespace scancrew::scenegen
