#pragma once

// The marching cubes tables (Lorensen & Cline 1987, "Marching cubes: a high resolution 3D
// surface construction algorithm"; thesis 1.3.3) in Paul Bourke's numbering ("Polygonising
// a scalar field", 1994, public domain data).
//
// Corner i of a cube sits at kMcCornerOffset[i] from the cube's min corner; edge j joins
// the corners kMcEdgeCorners[j]. A cube's configuration has bit i set when corner i is
// inside (signed distance < 0). Triangles of the table are wound so that their normal
// (b − a) × (c − a) points inside; the mesher reverses them to face outside.

#include <array>
#include <cstdint>

namespace scancrew::tsdf {

inline constexpr std::array<std::array<int, 3>, 8> kMcCornerOffset = {{
    {0, 0, 0},
    {1, 0, 0},
    {1, 1, 0},
    {0, 1, 0},
    {0, 0, 1},
    {1, 0, 1},
    {1, 1, 1},
    {0, 1, 1},
}};

inline constexpr std::array<std::array<int, 2>, 12> kMcEdgeCorners = {{
    {0, 1},
    {1, 2},
    {2, 3},
    {3, 0},
    {4, 5},
    {5, 6},
    {6, 7},
    {7, 4},
    {0, 4},
    {1, 5},
    {2, 6},
    {3, 7},
}};

struct McTables {
  std::array<uint16_t, 256> edges;                    // bit j: the surface cuts edge j
  std::array<std::array<int8_t, 16>, 256> triangles;  // edge triples, −1 terminated
};

// The tables (static data; thread safe).
const McTables& mc_tables();

}  // namespace scancrew::tsdf
