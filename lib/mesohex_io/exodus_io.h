#pragma once
// Exodus II output (Sandia's finite-element data model on NetCDF), for solvers such as Sierra, MOOSE or Peridigm.
// The Exodus library stays inside exodus_io.cpp.
#include <string>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

// Exodus side number (1..6) of each local face lf of kHexFaces: the Exodus HEX side k has the nodes
// 1-2-6-5, 2-3-7-6, 3-4-8-7, 1-5-8-4, 1-4-3-2, 5-6-7-8 (1-based), i.e. our front, right, back, left, bottom, top.
inline constexpr int kExodusSideOfHexFace[6] = {5, 6, 1, 2, 3, 4};

// Writes `mesh` as an Exodus II file in the 64-bit-offset NetCDF format (NetCDF 3, which every Exodus reader opens;
// not NetCDF-4/HDF5), atomically (temporary file beside `path`, then rename). Contents:
// - nodes: the mesh points (coordinate names x, y, z); node i is point i - 1.
// - elements: HEX8 with the VTK corner order (which is the Exodus HEX8 order). Without a partition one element block
//   (id 1, name "hexes") in hex order; with one, block p + 1 (name "partition_<p>") holds the hexes of part p, in hex
//   order. The element number map gives each element its hex id + 1 in both cases.
// - side set 1 named "boundary": every boundary quad as (element, Exodus side), in compute_hex_topology order.
// - when cell_scalars is given: element variable "scaled_jacobian" at time step 1 (time 0).
// Preconditions (checked by write_hex_mesh): indices in range, cell_scalars / partition empty or one per hex.
// Errors: InvalidInput for a mesh without hexes; IoError (naming the path and the Exodus message) when writing fails.
void write_exodus(const std::string& path, const HexMesh& mesh, const std::vector<double>& cell_scalars,
                  const std::vector<int>& partition);

}  // namespace mesohex
