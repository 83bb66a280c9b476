#pragma once
// Hex mesh file formats, chosen by extension: .mesh (MEDIT, default), .vtk (legacy ASCII 2.0), .vtu (VTK XML),
// .msh (Gmsh 4.1 ASCII), .inp (Abaqus C3D8, write only), .exo / .e (Exodus II, write only). Parse errors throw
// mesohex::Error naming file:line.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

// Reads the file (at most kMaxInputBytes of text_input.h) and parses it with read_hex_mesh_text.
HexMesh read_hex_mesh(const std::string& path);
// The same reader on a file's content held in memory: `format` is the extension without the dot (mesh, vtk, vtu, msh;
// case-insensitive), `name` stands for the file name in error messages ("<name>:<line>: <what>").
HexMesh read_hex_mesh_text(std::string_view text, std::string_view format, std::string_view name);

// Writes to a temporary file beside `path`, then renames it: a failure never leaves a half-written file.
// cell_scalars (may be empty): one value per hex, written as cell data named "scaled_jacobian" where the format allows
// (.vtk .vtu .msh; an element variable at time 0 in .exo).
// partition (may be empty): one part id (>= 0) per hex, written as cell data named "partition" (.vtk .vtu .msh), as
// the hex reference part + 1 (.mesh), as element sets PART_<p> (.inp), and as one element block per part (.exo).
void write_hex_mesh(const std::string& path, const HexMesh& mesh, const std::vector<double>& cell_scalars = {},
                    const std::vector<int>& partition = {});

// Writes `text` to `path` atomically (temporary file "<path>.tmp.<pid>.<n>" beside it + rename). Used for every
// output file of the project. First removes the stale temporaries of the same target (remove_stale_temporaries).
void write_file_atomically(const std::string& path, const std::string& text);

// Removes "<path>.tmp.<pid>.<n>" files (our naming only, regular files only) whose writer process <pid> no longer
// exists: what a run killed while writing `path` left behind. Returns how many were removed; errors are ignored.
int remove_stale_temporaries(const std::string& path);

// The same for writers that need a file name (libraries that open the file themselves): `write_to` gets the name of
// a new empty temporary file beside `path` and writes the whole file there; it is then renamed to `path`. When
// `write_to` throws, the temporary file is removed and the exception passes on.
void write_atomically_via(const std::string& path, const std::function<void(const std::string& temporary)>& write_to);

}  // namespace mesohex
