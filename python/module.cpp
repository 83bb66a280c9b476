// _mesohex: the Python binding of the mesohex library (imported through the `mesohex` package, see __init__.py).
// A thin layer: numpy <-> the library's plain arrays, keyword options -> the same option structs the CLI fills, the
// library's JSON reports -> dicts, mesohex::Error -> Python exceptions (mesohex.Error and one subclass per ErrorCode,
// with `.code` = the CLI's exit status). No meshing logic here. Long calls release the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <tbb/global_control.h>

#include "mesohex/auto_skeleton.h"
#include "mesohex/core/error.h"
#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/skeleton.h"
#include "mesohex/mesh.h"
#include "mesohex/mesh_report.h"
#include "mesohex/post/partition.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/generators.h"
#include "mesohex/surface/medial_axis.h"
#include "mesohex/surface/skeletonize.h"
#include "mesohex/surface/thicken.h"
#include "mesohex_io/hex_io.h"
#include "mesohex_io/medial_io.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

namespace py = pybind11;
using namespace mesohex;

namespace {

// ---------------------------------------------------------------------------------------------------------------
// numpy <-> plain arrays

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

py::array_t<double> points_to_numpy(const std::vector<Vec3>& points) {
    py::array_t<double> a({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
    auto r = a.mutable_unchecked<2>();
    for (std::size_t v = 0; v < points.size(); ++v)
        for (int c = 0; c < 3; ++c) r(static_cast<py::ssize_t>(v), c) = points[v][c];
    return a;
}

template <std::size_t N>
py::array_t<std::int32_t> cells_to_numpy(const std::vector<std::array<int, N>>& cells) {
    py::array_t<std::int32_t> a({static_cast<py::ssize_t>(cells.size()), static_cast<py::ssize_t>(N)});
    auto r = a.mutable_unchecked<2>();
    for (std::size_t i = 0; i < cells.size(); ++i)
        for (std::size_t k = 0; k < N; ++k) r(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(k)) = cells[i][k];
    return a;
}

template <class T>
py::array_t<T> vector_to_numpy(const std::vector<T>& values) {
    py::array_t<T> a(static_cast<py::ssize_t>(values.size()));
    std::copy(values.begin(), values.end(), a.mutable_data());
    return a;
}

[[noreturn]] void invalid(const std::string& message) { throw Error(ErrorCode::InvalidInput, message); }

std::vector<Vec3> points_from_numpy(const DoubleArray& a, const char* what) {
    if (a.ndim() != 2 || a.shape(1) != 3)
        invalid(std::string(what) + ": expected an array of shape (n, 3), got " + std::to_string(a.ndim()) +
                " dimension(s)" + (a.ndim() == 2 ? " with " + std::to_string(a.shape(1)) + " columns" : ""));
    std::vector<Vec3> points(static_cast<std::size_t>(a.shape(0)));
    auto r = a.unchecked<2>();
    for (std::size_t v = 0; v < points.size(); ++v) {
        for (int c = 0; c < 3; ++c) points[v][c] = r(static_cast<py::ssize_t>(v), c);
        if (!is_finite(points[v])) invalid(std::string(what) + ": row " + std::to_string(v) + " is not finite");
    }
    return points;
}

// Rows of N indices, each in [0, num_points).
template <std::size_t N>
std::vector<std::array<int, N>> cells_from_numpy(const IntArray& a, std::size_t num_points, const char* what) {
    if (a.ndim() != 2 || a.shape(1) != static_cast<py::ssize_t>(N))
        invalid(std::string(what) + ": expected an integer array of shape (m, " + std::to_string(N) + ")");
    std::vector<std::array<int, N>> cells(static_cast<std::size_t>(a.shape(0)));
    auto r = a.unchecked<2>();
    for (std::size_t i = 0; i < cells.size(); ++i)
        for (std::size_t k = 0; k < N; ++k) {
            const std::int64_t v = r(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(k));
            if (v < 0 || v >= static_cast<std::int64_t>(num_points))
                invalid(std::string(what) + ": row " + std::to_string(i) + " refers to vertex " + std::to_string(v) +
                        " (there are " + std::to_string(num_points) + ")");
            cells[i][k] = static_cast<int>(v);
        }
    return cells;
}

// ---------------------------------------------------------------------------------------------------------------
// JSON text (the library's reports) -> Python objects

py::object json_to_python(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

// ---------------------------------------------------------------------------------------------------------------
// Errors

const char* exception_name(ErrorCode code) {
    switch (code) {
        case ErrorCode::InvalidInput: return "InvalidInput";
        case ErrorCode::UnsupportedConfiguration: return "UnsupportedConfiguration";
        case ErrorCode::IoError: return "IoError";
        case ErrorCode::NumericalFailure: return "NumericalFailure";
    }
    return "Error";
}

void register_errors(py::module_& m) {
    py::object base = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
        "mesohex.Error", "A mesohex error: .code is the exit status the CLI gives for it, .category its kind.",
        PyExc_RuntimeError, nullptr));
    base.attr("code") = 1;
    base.attr("category") = "Error";
    m.attr("Error") = base;
    for (ErrorCode code : {ErrorCode::InvalidInput, ErrorCode::UnsupportedConfiguration, ErrorCode::IoError,
                           ErrorCode::NumericalFailure}) {
        const std::string name = exception_name(code);
        py::object cls =
            py::reinterpret_steal<py::object>(PyErr_NewException(("mesohex." + name).c_str(), base.ptr(), nullptr));
        cls.attr("code") = exit_code(code);
        cls.attr("category") = name;
        m.attr(name.c_str()) = cls;
    }
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const Error& e) {
            py::object cls = py::module_::import("mesohex._mesohex").attr(exception_name(e.code()));
            PyErr_SetString(cls.ptr(), e.what());
        }
    });
}

// ---------------------------------------------------------------------------------------------------------------
// Threads: 0 = all cores (the library's default), n > 0 = at most n for the duration of one call.

struct ThreadLimit {
    explicit ThreadLimit(int threads) {
        if (threads < 0) invalid("threads must be >= 0 (0 = all cores), got " + std::to_string(threads));
        if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    }
    std::optional<tbb::global_control> limit;
};

// ---------------------------------------------------------------------------------------------------------------
// Bindings of the data types: immutable values, built from numpy arrays (indices checked), read as numpy copies.

void bind_types(py::module_& m) {
    py::class_<HexMesh>(m, "HexMesh", "An all-hex mesh: vertices (n, 3) float64, hexes (m, 8) int32 in VTK order.")
        .def(py::init([](const DoubleArray& vertices, const IntArray& hexes) {
                 HexMesh mesh;
                 mesh.points = points_from_numpy(vertices, "vertices");
                 mesh.hexes = cells_from_numpy<8>(hexes, mesh.points.size(), "hexes");
                 return mesh;
             }),
             py::arg("vertices"), py::arg("hexes"))
        .def_property_readonly("vertices", [](const HexMesh& mesh) { return points_to_numpy(mesh.points); })
        .def_property_readonly("hexes", [](const HexMesh& mesh) { return cells_to_numpy(mesh.hexes); })
        .def("__eq__", [](const HexMesh& a, const HexMesh& b) { return a == b; })
        .def("__repr__", [](const HexMesh& mesh) {
            return "<mesohex.HexMesh: " + std::to_string(mesh.points.size()) + " vertices, " +
                   std::to_string(mesh.hexes.size()) + " hexes>";
        });

    py::class_<TriangleMesh>(m, "Surface",
                             "A triangle surface: vertices (n, 3) float64, triangles (m, 3) int32, outward oriented.")
        .def(py::init([](const DoubleArray& vertices, const IntArray& triangles) {
                 TriangleMesh mesh;
                 mesh.points = points_from_numpy(vertices, "vertices");
                 mesh.triangles = cells_from_numpy<3>(triangles, mesh.points.size(), "triangles");
                 return mesh;
             }),
             py::arg("vertices"), py::arg("triangles"))
        .def_property_readonly("vertices", [](const TriangleMesh& mesh) { return points_to_numpy(mesh.points); })
        .def_property_readonly("triangles", [](const TriangleMesh& mesh) { return cells_to_numpy(mesh.triangles); })
        .def("__eq__", [](const TriangleMesh& a, const TriangleMesh& b) { return a == b; })
        .def("__repr__", [](const TriangleMesh& mesh) {
            return "<mesohex.Surface: " + std::to_string(mesh.points.size()) + " vertices, " +
                   std::to_string(mesh.triangles.size()) + " triangles>";
        });

    py::class_<Skeleton>(m, "Skeleton",
                         "A meso-skeleton: points (n, 3), radii (n,) or empty, edges (e, 2) int32, faces (list of "
                         "vertex lists: the quad leaflets).")
        .def(py::init([](const DoubleArray& points, const IntArray& edges, const std::vector<std::vector<int>>& faces,
                         std::optional<DoubleArray> radii) {
                 Skeleton s;
                 s.points = points_from_numpy(points, "points");
                 s.edges = cells_from_numpy<2>(edges, s.points.size(), "edges");
                 for (std::size_t f = 0; f < faces.size(); ++f)
                     for (int v : faces[f])
                         if (v < 0 || static_cast<std::size_t>(v) >= s.points.size())
                             invalid("faces: face " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                                     " (there are " + std::to_string(s.points.size()) + ")");
                 s.faces = faces;
                 add_face_edges(s);
                 if (radii && radii->size() > 0) {
                     if (radii->ndim() != 1 || static_cast<std::size_t>(radii->shape(0)) != s.points.size())
                         invalid("radii: expected one per point (" + std::to_string(s.points.size()) + ")");
                     s.radii.assign(radii->data(), radii->data() + radii->size());
                 }
                 return s;
             }),
             py::arg("points"), py::arg("edges"), py::arg("faces") = std::vector<std::vector<int>>{},
             py::arg("radii") = py::none())
        .def_property_readonly("points", [](const Skeleton& s) { return points_to_numpy(s.points); })
        .def_property_readonly("radii", [](const Skeleton& s) { return vector_to_numpy(s.radii); })
        .def_property_readonly("edges", [](const Skeleton& s) { return cells_to_numpy(s.edges); })
        .def_property_readonly("faces", [](const Skeleton& s) { return s.faces; })
        .def("__eq__", [](const Skeleton& a, const Skeleton& b) { return a == b; })
        .def("__repr__", [](const Skeleton& s) {
            return "<mesohex.Skeleton: " + std::to_string(s.points.size()) + " points, " +
                   std::to_string(s.edges.size()) + " edges, " + std::to_string(s.faces.size()) + " faces>";
        });
}

// ---------------------------------------------------------------------------------------------------------------
// Files, quality, partition, generate, thicken

py::dict partition_dict(const Partition& p) {
    py::dict d = json_to_python(partition_to_json(p));
    d["part"] = vector_to_numpy(p.part);
    return d;
}

void bind_functions(py::module_& m) {
    m.def("read_skeleton", &read_skeleton, py::arg("path"), py::call_guard<py::gil_scoped_release>(),
          "Reads a skeleton (.skel .cg .cgr .ig .obj).");
    m.def("write_skeleton", &write_skeleton, py::arg("path"), py::arg("skeleton"),
          py::call_guard<py::gil_scoped_release>(), "Writes a skeleton (.obj or .ig), atomically.");
    m.def("read_surface", &read_surface, py::arg("path"), py::call_guard<py::gil_scoped_release>(),
          "Reads a triangle surface (.off .obj .stl .ply).");
    m.def("write_surface", &write_surface, py::arg("path"), py::arg("surface"),
          py::call_guard<py::gil_scoped_release>(), "Writes a triangle surface (.off .obj .stl), atomically.");
    m.def("read_hex_mesh", &read_hex_mesh, py::arg("path"), py::call_guard<py::gil_scoped_release>(),
          "Reads a hex mesh (.mesh .vtk .vtu .msh).");
    m.def(
        "write_hex_mesh",
        [](const std::string& path, const HexMesh& mesh, std::optional<DoubleArray> scaled_jacobian,
           std::optional<IntArray> partition) {
            std::vector<double> sj;
            if (scaled_jacobian) sj.assign(scaled_jacobian->data(), scaled_jacobian->data() + scaled_jacobian->size());
            std::vector<int> part;
            if (partition) part.assign(partition->data(), partition->data() + partition->size());
            py::gil_scoped_release release;
            write_hex_mesh(path, mesh, sj, part);
        },
        py::arg("path"), py::arg("mesh"), py::arg("scaled_jacobian") = py::none(), py::arg("partition") = py::none(),
        "Writes a hex mesh (.mesh .vtk .vtu .msh .inp .exo .e, by extension), atomically; optional per-hex cell data "
        "'scaled_jacobian' and 'partition' (see docs/formats.md).");

    m.def(
        "quality",
        [](const HexMesh& mesh) {
            std::string text;
            {
                py::gil_scoped_release release;
                text = quality_to_json(compute_quality(mesh));
            }
            return json_to_python(text);
        },
        py::arg("mesh"), "The quality report of a hex mesh as a dict (the keys of `mesohex quality --json`).");
    m.def(
        "scaled_jacobians",
        [](const HexMesh& mesh) {
            std::vector<double> sj;
            {
                py::gil_scoped_release release;
                sj = scaled_jacobians(mesh);
            }
            return vector_to_numpy(sj);
        },
        py::arg("mesh"), "Per-hex scaled Jacobian (Verdict definition), float64 array of length m.");
    m.def(
        "partition",
        [](const HexMesh& mesh, int parts, int seed) {
            Partition p;
            {
                py::gil_scoped_release release;
                p = partition_hexes(mesh, {.parts = parts, .seed = seed});
            }
            return partition_dict(p);
        },
        py::arg("mesh"), py::arg("parts"), py::arg("seed") = 1,
        "METIS k-way partition of the hexes (face adjacency): dict with 'part' (int32 per hex), 'parts', "
        "'edge_cut', 'imbalance', 'part_sizes'.");

    m.def("generator_names", &generator_names, "The names `generate` accepts.");
    m.def(
        "generate",
        [](const std::string& name, int n, int m_, int quarter_turns, double edge_length, double radius_scale) {
            GeneratorOptions o;
            o.n = n;
            o.m = m_;
            o.quarter_turns = quarter_turns;
            o.edge_length = edge_length;
            o.radius_scale = radius_scale;
            return generate_skeleton(name, o);
        },
        py::arg("name"), py::arg("n") = 0, py::arg("m") = 0, py::arg("quarter_turns") = -1,
        py::arg("edge_length") = 1.0, py::arg("radius_scale") = 1.0,
        "A procedural skeleton, as `mesohex generate NAME -n N -m M --quarter-turns Q --edge-length L "
        "--radius-scale S`.");
    m.def(
        "thicken",
        [](const Skeleton& skeleton, double radius, double resolution, long max_grid_points, int threads) {
            ThreadLimit limit(threads);
            ThickenOptions o;
            o.radius = radius;
            o.cells_per_radius = resolution;
            o.max_grid_points = max_grid_points;
            if (skeleton.radii.empty() && !(radius > 0))
                invalid("thicken: the skeleton has no radii; give one with radius=R");
            py::gil_scoped_release release;
            return thicken(skeleton, o);
        },
        py::arg("skeleton"), py::arg("radius") = 0.0, py::arg("resolution") = ThickenOptions{}.cells_per_radius,
        py::arg("max_grid_points") = ThickenOptions{}.max_grid_points, py::arg("threads") = 0,
        "The closed surface of the domain a skeleton with radii describes, as `mesohex thicken --radius R "
        "--resolution C --max-grid-points N`.");
    m.def(
        "medial",
        [](const TriangleMesh& surface, const std::string& output, int target_vertices, double sample_spacing) {
            MedialAxisOptions o;
            o.target_vertices = target_vertices;
            o.sample_spacing = sample_spacing;
            MedialAxis ma;
            {
                py::gil_scoped_release release;
                ma = compute_medial_axis(surface, o);
                if (!output.empty()) write_medial_mesh(output, ma.medial);
            }
            py::dict d;
            d["medial"] = ma.medial;
            d["samples"] = ma.samples;
            d["sheets"] = ma.sheets;
            d["curves"] = ma.curves;
            d["euler_characteristic"] = ma.euler;
            d["sheet_fraction"] = ma.sheet_fraction;
            d["bbox_diagonal"] = ma.bbox_diagonal;
            return d;
        },
        py::arg("surface"), py::kw_only(), py::arg("output") = "",
        py::arg("target_vertices") = MedialAxisOptions{}.target_vertices,
        py::arg("sample_spacing") = MedialAxisOptions{}.sample_spacing,
        "The simplified medial mesh of a closed, manifold surface, as `mesohex medial SURFACE -o OUT.ma`: a dict with "
        "'medial' (a Skeleton: sphere centres, radii, curve edges and triangles), 'sheets', 'curves', "
        "'euler_characteristic', 'sheet_fraction', 'samples', 'bbox_diagonal'; written as .ma when output is given.");
}

// ---------------------------------------------------------------------------------------------------------------
// mesh and auto: keyword options -> MeshOptions as the CLI's flags do (same names, '-' -> '_'), mesh_skeleton, the
// mesh file and the report (mesh_report, the same keys as --report).

struct MeshResult {
    HexMesh mesh;
    std::vector<double> scaled_jacobian;
    std::optional<std::vector<int>> partition;
    Skeleton skeleton;  // the skeleton meshed (after resampling)
    py::object report;  // dict
    int status = 0;     // 0, or 5 when the mesh has inverted hexes or is invalid (the CLI's exit status)
};

// The CLI's flags of `mesh` (with_radius) or `auto`, read from keyword arguments onto the library's defaults.
struct MeshCall {
    MeshOptions options;
    int threads = 0;
};

MeshCall mesh_call(const py::kwargs& kwargs, bool with_radius) {
    MeshCall call;
    MeshOptions& o = call.options;
    const std::set<std::string> flags = {"radius",        "no_resample", "raw",        "radius_from_surface",
                                         "radius_factor", "levels",      "size",       "refine",
                                         "pad",           "no_pad",      "no_fit",     "no_untangle",
                                         "no_smooth",     "no_retry",    "iterations", "fit_weight",
                                         "improve_below", "partitions",  "threads",    "no_trim_tips"};
    for (const auto& item : kwargs) {
        const std::string key = py::cast<std::string>(item.first);
        const py::handle value = item.second;
        if (!flags.count(key) || (key == "radius" && !with_radius)) {
            std::string valid;
            for (const std::string& f : flags)
                if (f != "radius" || with_radius) valid += (valid.empty() ? "" : ", ") + f;
            invalid("unknown option '" + key + "' (valid: " + valid + ")");
        }
        auto flag = [&] { return py::cast<bool>(value); };
        if (key == "radius")
            o.pipeline.radius = py::cast<double>(value);
        else if (key == "no_resample")
            o.pipeline.resample = !flag();
        else if (key == "raw")
            o.finish = !flag();
        else if (key == "radius_from_surface")
            o.radius_from_surface = flag();
        else if (key == "radius_factor")
            o.radius_factor = py::cast<double>(value);
        else if (key == "levels")
            o.finishing.levels = py::cast<int>(value);
        else if (key == "size")
            o.finishing.size = py::cast<double>(value);
        else if (key == "refine") {
            const std::string r = py::cast<std::string>(value);
            if (r == "uniform")
                o.finishing.refinement = FinishOptions::Refinement::Uniform;
            else if (r == "longitudinal")
                o.finishing.refinement = FinishOptions::Refinement::Longitudinal;
            else if (r == "radial")
                o.finishing.refinement = FinishOptions::Refinement::Radial;
            else
                invalid("refine: '" + r + "' is not one of uniform, longitudinal, radial");
        } else if (key == "pad") {
            const std::string m = py::cast<std::string>(value);
            if (m != "all" && m != "selective" && m != "none")
                invalid("pad: '" + m + "' is not one of all, selective, none");
            o.finishing.pad = m != "none";
            o.finishing.pad_selective = m == "selective";
        } else if (key == "no_pad")
            o.finishing.pad = !flag();
        else if (key == "no_fit") {
            if (flag()) o.finishing.fit = o.finishing.untangle = false;
        } else if (key == "no_untangle") {
            if (flag()) o.finishing.untangle = false;
        } else if (key == "no_smooth")
            o.finishing.smooth = !flag();
        else if (key == "no_retry") {
            if (flag()) o.retry = o.structural_retry = false;  // as the CLI's --no-retry: one attempt
        } else if (key == "no_trim_tips")
            o.trim_unheld_tips = !flag();
        else if (key == "iterations")
            o.finishing.fitting.max_iterations = py::cast<int>(value);
        else if (key == "fit_weight") {
            o.finishing.fitting.lambda = py::cast<double>(value);
            if (!(o.finishing.fitting.lambda > 0)) invalid("fit_weight must be > 0");
        } else if (key == "improve_below") {
            o.finishing.improve_sj = py::cast<double>(value);
            if (!(o.finishing.improve_sj >= 0 && o.finishing.improve_sj <= 0.99))
                invalid("improve_below must be in [0, 0.99]");
        } else if (key == "partitions") {
            o.partitions = py::cast<int>(value);
            if (o.partitions < 0) invalid("partitions must be >= 1 (0 = no partition)");
        } else if (key == "threads")
            call.threads = py::cast<int>(value);
    }
    return call;
}

std::string path_of(const py::object& value) {
    return py::cast<std::string>(py::module_::import("os").attr("fspath")(value));
}
bool is_path(const py::object& value) { return py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__"); }

double ms_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

// Names of a mesh call, as the report gives them.
struct MeshNames {
    std::string input, surface, output, report;
};

// mesh_skeleton + the mesh file (when output is given) + the report (written when a path is given), as run_mesh_job
// does. `extra` (an object, may be null): members added to the report ("timings_ms" merged into its timings, plus
// "total" from `total_start`). Called without the GIL.
MeshResult run_mesh(const Skeleton& skeleton, const TriangleMesh* domain, const MeshCall& call, const MeshNames& names,
                    std::chrono::steady_clock::time_point start, const nlohmann::json* extra,
                    std::chrono::steady_clock::time_point total_start, std::string& report_text) {
    const auto t_mesh = std::chrono::steady_clock::now();
    MeshOptions options = call.options;
    options.progress = [](const MeshProgress&) {
        // Lets Ctrl-C interrupt a long run: the exception propagates out of mesh_skeleton.
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    };
    MeshRun run = mesh_skeleton(skeleton, domain, options);
    const auto t_write = std::chrono::steady_clock::now();
    if (!names.output.empty())
        write_hex_mesh(names.output, run.mesh(), run.quality().sj,
                       run.partition ? run.partition->part : std::vector<int>{});
    const auto t_end = std::chrono::steady_clock::now();
    nlohmann::json rep = mesh_report(run, ReportContext{names.input, names.output, names.surface,
                                                        ms_between(start, t_mesh), ms_between(t_write, t_end)});
    if (extra) {
        for (const auto& [key, value] : extra->items())
            if (key != "timings_ms") rep[key] = value;
        if (extra->contains("timings_ms"))
            for (const auto& [key, value] : (*extra)["timings_ms"].items()) rep["timings_ms"][key] = value;
        rep["timings_ms"]["total"] = ms_between(total_start, t_end);
    }
    report_text = rep.dump();
    if (!names.report.empty()) write_file_atomically(names.report, rep.dump(2) + "\n");
    MeshResult r;
    r.mesh = run.mesh();
    r.scaled_jacobian = run.quality().sj;
    if (run.partition) r.partition = run.partition->part;
    r.skeleton = run.pipeline.skeleton;
    r.status = run.exit_status();
    return r;
}

MeshResult mesh_py(const py::object& skeleton_arg, const py::object& surface_arg, const std::string& output,
                   const std::string& report, const py::kwargs& kwargs) {
    const MeshCall call = mesh_call(kwargs, true);
    ThreadLimit limit(call.threads);
    MeshNames names{"", "", output, report};
    const auto t0 = std::chrono::steady_clock::now();
    std::string report_text;
    MeshResult result;
    {
        Skeleton skeleton;
        std::optional<TriangleMesh> domain;
        if (is_path(skeleton_arg))
            names.input = path_of(skeleton_arg);
        else
            skeleton = py::cast<Skeleton>(skeleton_arg);
        if (!surface_arg.is_none()) {
            if (is_path(surface_arg))
                names.surface = path_of(surface_arg);
            else
                domain = py::cast<TriangleMesh>(surface_arg);
        }
        py::gil_scoped_release release;
        if (!names.input.empty()) skeleton = read_skeleton(names.input);
        if (!names.surface.empty()) domain = read_surface(names.surface);
        try {
            result = run_mesh(skeleton, domain ? &*domain : nullptr, call, names, t0, nullptr, t0, report_text);
        } catch (const Error& e) {
            if (names.input.empty()) throw;
            throw Error(e.code(), names.input + ": " + e.what(), e.where());  // name the file, as the CLI does
        }
    }
    result.report = json_to_python(report_text);
    return result;
}

MeshResult auto_py(const py::object& surface_arg, const std::string& output, const std::string& report,
                   const std::string& skeleton, const py::kwargs& kwargs) {
    if (skeleton != "auto" && skeleton != "curve" && skeleton != "meso")
        throw Error(ErrorCode::InvalidInput, "skeleton must be 'auto', 'curve' or 'meso', not '" + skeleton + "'");
    MeshCall call = mesh_call(kwargs, false);
    call.options.structural_retry = false;  // as `mesohex auto`: off until measured on its surfaces
    ThreadLimit limit(call.threads);
    MeshNames names{"", "", output, report};
    std::string report_text;
    MeshResult result;
    {
        std::optional<TriangleMesh> domain;
        if (is_path(surface_arg))
            names.surface = path_of(surface_arg);
        else
            domain = py::cast<TriangleMesh>(surface_arg);
        py::gil_scoped_release release;
        const auto t0 = std::chrono::steady_clock::now();
        if (!names.surface.empty()) domain = read_surface(names.surface);
        const auto t1 = std::chrono::steady_clock::now();
        AutoSkeletonOptions so;
        so.kind = skeleton == "curve"  ? SkeletonKind::Curve
                  : skeleton == "meso" ? SkeletonKind::Meso
                                       : SkeletonKind::Auto;
        const AutoSkeleton chosen = choose_skeleton(*domain, so);  // as `mesohex auto`: curve or medial meso-skeleton
        const auto t2 = std::chrono::steady_clock::now();
        // As `mesohex auto`: the skeleton used is written beside the mesh (OUT.skeleton.obj) when there is a file,
        // and the medial mesh (OUT.medial.ma) when one was computed.
        std::string medial_path;
        if (!output.empty()) {
            names.input = std::filesystem::path(output).replace_extension(".skeleton.obj").string();
            write_skeleton(names.input, chosen.skeleton);
            if (chosen.medial_computed) {
                medial_path = std::filesystem::path(output).replace_extension(".medial.ma").string();
                write_medial_mesh(medial_path, chosen.medial.medial);
            }
        }
        const auto t3 = std::chrono::steady_clock::now();
        nlohmann::json extra = auto_skeleton_report(chosen, so, names.input, medial_path);
        extra["timings_ms"] = {{"read_surface", ms_between(t0, t1)},
                               {"skeletonize", ms_between(t1, t2)},
                               {"write_skeleton", ms_between(t2, t3)}};
        result = run_mesh(chosen.skeleton, &*domain, call, names, t3, &extra, t0, report_text);
    }
    result.report = json_to_python(report_text);
    return result;
}

void bind_meshing(py::module_& m) {
    py::class_<MeshResult>(m, "MeshResult",
                           "A meshing result: the hex mesh, its per-hex scaled Jacobian, the partition (when asked "
                           "for), the skeleton meshed, the report (dict, the keys of --report) and the status.")
        .def_readonly("mesh", &MeshResult::mesh)
        .def_property_readonly("vertices", [](const MeshResult& r) { return points_to_numpy(r.mesh.points); })
        .def_property_readonly("hexes", [](const MeshResult& r) { return cells_to_numpy(r.mesh.hexes); })
        .def_property_readonly("scaled_jacobian",
                               [](const MeshResult& r) { return vector_to_numpy(r.scaled_jacobian); })
        .def_property_readonly("partition",
                               [](const MeshResult& r) -> py::object {
                                   if (!r.partition) return py::none();
                                   return vector_to_numpy(*r.partition);
                               })
        .def_readonly("skeleton", &MeshResult::skeleton)
        .def_readonly("report", &MeshResult::report)
        .def_readonly("status", &MeshResult::status, "0, or 5 when the mesh has inverted hexes (the CLI's exit status)")
        .def("__repr__", [](const MeshResult& r) {
            return "<mesohex.MeshResult: " + std::to_string(r.mesh.points.size()) + " vertices, " +
                   std::to_string(r.mesh.hexes.size()) + " hexes, status " + std::to_string(r.status) + ">";
        });
    m.def("mesh", &mesh_py, py::arg("skeleton"), py::arg("surface") = py::none(), py::kw_only(), py::arg("output") = "",
          py::arg("report") = "",
          "Meshes a skeleton (a Skeleton or a file path) as `mesohex mesh`: raw mesh, then, with a surface (a Surface "
          "or a path), pad, subdivide, fit, untangle, smooth. Keyword options are the CLI's flags with '_' for '-' "
          "(radius, no_resample, raw, radius_from_surface, radius_factor, levels, size, refine, pad, no_pad, no_fit, "
          "no_untangle, no_smooth, no_retry, iterations, fit_weight, improve_below, partitions, threads). output / "
          "report: files to write (optional). Returns a MeshResult.");
    m.def("auto", &auto_py, py::arg("surface"), py::kw_only(), py::arg("output") = "", py::arg("report") = "",
          py::arg("skeleton") = "auto",
          "Surface -> hex mesh as `mesohex auto`: a skeleton of the surface (a Surface or a path; skeleton='auto' "
          "chooses the curve skeleton for tubes and the medial meso-skeleton for flat or thin parts, 'curve' / "
          "'meso' force one), then mesh in it. The same keyword options as mesh() except radius. With an output "
          "file, the skeleton used is written beside it (OUT.skeleton.obj). Returns a MeshResult.");
}

}  // namespace

PYBIND11_MODULE(_mesohex, m) {
    m.doc() = "mesohex: all-hex meshes guided by meso-skeletons (the compiled part of the `mesohex` package).";
    register_errors(m);
    bind_types(m);
    bind_functions(m);
    bind_meshing(m);
}
