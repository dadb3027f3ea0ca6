// The bindings behind the Python package `foldfill` (python/foldfill/__init__.py
// holds the documented API and passes its checked arguments here): meshes as
// NumPy arrays in and out, the library's errors as foldfill.Error subclasses,
// the fill run with the GIL released.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <climits>
#include <exception>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/fill.h"
#include "foldfill/io.h"
#include "foldfill/obstacles.h"

namespace py = pybind11;

namespace foldfill::python {
namespace {

using Vertices = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Faces = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;

// The Python class of each kind of error, created at import.
std::map<ErrorKind, PyObject*>& error_classes() {
  static std::map<ErrorKind, PyObject*> classes;
  return classes;
}
PyObject* cancelled_class = nullptr;

[[noreturn]] void usage(const std::string& message) { throw UsageError(message); }

std::string shape_of(const py::array& array) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d)
    text += (d ? ", " : "") + std::to_string(array.shape(d));
  return text + (array.ndim() == 1 ? ",)" : ")");
}

// `array` as an (n, 3) array of `T`; UsageError naming `what` otherwise.
template <class Array>
Array as_rows_of_three(const py::object& object, const std::string& what) {
  const py::array any = py::array::ensure(object);
  if (!any) usage(what + ": not an array");
  if (any.ndim() != 2 || any.shape(1) != 3) {
    usage(what + ": expected an array of shape (n, 3), got shape " + shape_of(any));
  }
  const char kind = any.dtype().kind();
  if constexpr (std::is_same_v<Array, Faces>) {
    if (kind != 'i' && kind != 'u') {
      usage(what + ": expected integer vertex indices, got dtype " +
            py::str(any.dtype()).cast<std::string>());
    }
  } else if (kind != 'f' && kind != 'i' && kind != 'u') {
    usage(what + ": expected numbers, got dtype " + py::str(any.dtype()).cast<std::string>());
  }
  Array typed = Array::ensure(any);
  if (!typed) usage(what + ": cannot be converted");
  return typed;
}

// A mesh of the arrays `vertices` (n, 3) and `faces` (m, 3), checked as
// read_mesh checks a file (validate_mesh).
Mesh mesh_of(const py::object& vertices, const py::object& faces, const std::string& source) {
  const Vertices v = as_rows_of_three<Vertices>(vertices, "vertices");
  const Faces f = as_rows_of_three<Faces>(faces, "faces");
  Mesh mesh;
  mesh.positions.resize(static_cast<size_t>(v.shape(0)));
  const double* vd = v.data();
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    mesh.positions[i] = {vd[3 * i], vd[3 * i + 1], vd[3 * i + 2]};
  mesh.faces.resize(static_cast<size_t>(f.shape(0)));
  const int64_t* fd = f.data();
  for (size_t i = 0; i < mesh.faces.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const int64_t index = fd[3 * i + c];
      // Beyond int, an index is out of range of any mesh; say so as
      // validate_mesh does for the others.
      if (index < 0 || index >= static_cast<int64_t>(mesh.positions.size())) {
        throw BadFaceError(source + ": face " + std::to_string(i) + ": face vertex " +
                           std::to_string(index) + " out of range (mesh has " +
                           std::to_string(mesh.positions.size()) + " vertices)");
      }
      mesh.faces[i][c] = static_cast<int>(index);
    }
  }
  validate_mesh(mesh, source);
  return mesh;
}

py::array_t<double> vertices_of(const Mesh& mesh) {
  py::array_t<double> out({static_cast<py::ssize_t>(mesh.positions.size()), py::ssize_t{3}});
  double* d = out.mutable_data();
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    for (int c = 0; c < 3; ++c) d[3 * i + c] = mesh.positions[i][c];
  return out;
}

py::array_t<int64_t> faces_of(const Mesh& mesh) {
  py::array_t<int64_t> out({static_cast<py::ssize_t>(mesh.faces.size()), py::ssize_t{3}});
  int64_t* d = out.mutable_data();
  for (size_t i = 0; i < mesh.faces.size(); ++i)
    for (int c = 0; c < 3; ++c) d[3 * i + c] = mesh.faces[i][c];
  return out;
}

// One mark per element: `marks`, or -1 for every element when it is empty.
py::array_t<int64_t> marks_of(const std::vector<int>& marks, size_t count) {
  py::array_t<int64_t> out(static_cast<py::ssize_t>(count));
  int64_t* d = out.mutable_data();
  for (size_t i = 0; i < count; ++i) d[i] = marks.empty() ? -1 : marks[i];
  return out;
}

std::vector<int> marks_from(const py::object& object, size_t count, const std::string& what) {
  if (object.is_none()) return {};
  const py::array any = py::array::ensure(object);
  if (!any || any.ndim() != 1 || static_cast<size_t>(any.shape(0)) != count ||
      (any.dtype().kind() != 'i' && any.dtype().kind() != 'u')) {
    usage(what + ": expected " + std::to_string(count) + " integers (a hole id or -1 each)");
  }
  const auto typed = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(any);
  std::vector<int> marks(count);
  for (size_t i = 0; i < count; ++i) {
    const int64_t value = typed.data()[i];
    if (value < -1 || value > INT_MAX)
      usage(what + ": " + std::to_string(value) + " is not -1 or a hole id");
    marks[i] = static_cast<int>(value);
  }
  return marks;
}

py::tuple read_arrays(const std::string& path) {
  std::vector<std::string> warnings;
  const Mesh mesh = read_mesh(path, &warnings);
  return py::make_tuple(vertices_of(mesh), faces_of(mesh), warnings);
}

void write_arrays(const std::string& path, const py::object& vertices, const py::object& faces,
                  const py::object& vertex_hole, const py::object& face_hole, bool ascii) {
  Mesh mesh = mesh_of(vertices, faces, path);
  mesh.vertex_hole = marks_from(vertex_hole, mesh.positions.size(), "new_vertices");
  mesh.face_hole = marks_from(face_hole, mesh.faces.size(), "new_faces");
  // A writer marks both or neither.
  if (mesh.vertex_hole.empty() != mesh.face_hole.empty()) {
    if (mesh.vertex_hole.empty()) mesh.vertex_hole.assign(mesh.positions.size(), -1);
    if (mesh.face_hole.empty()) mesh.face_hole.assign(mesh.faces.size(), -1);
  }
  WriteOptions options;
  options.binary = !ascii;
  py::gil_scoped_release release;
  write_mesh(mesh, path, options);
}

HoleSelection selection_of(const std::string& mode, const std::vector<int>& ids,
                           const std::vector<std::array<double, 3>>& near, int keep_open,
                           int max_hole_size) {
  HoleSelection selection;
  if (mode == "default") {
    selection.mode = HoleSelection::Mode::Default;
  } else if (mode == "all") {
    selection.mode = HoleSelection::Mode::All;
  } else if (mode == "ids") {
    selection.mode = HoleSelection::Mode::Ids;
  } else if (mode == "near") {
    selection.mode = HoleSelection::Mode::Near;
  } else if (mode == "keep_open") {
    selection.mode = HoleSelection::Mode::KeepOpen;
    selection.keep_open = keep_open;
  } else {
    usage("holes: unknown selection '" + mode + "'");
  }
  selection.ids = ids;
  for (const auto& p : near) selection.near.push_back({p[0], p[1], p[2]});
  selection.max_hole_size = max_hole_size;
  return selection;
}

std::string list_holes(const py::object& vertices, const py::object& faces, int keep_open,
                       const std::string& source) {
  const Mesh mesh = mesh_of(vertices, faces, source);
  FillRequest request;
  request.source = source;
  if (keep_open >= 0) request.selection = selection_of("keep_open", {}, {}, keep_open, 0);
  py::gil_scoped_release release;
  const ChosenHoles chosen = choose_holes(mesh, request);
  nlohmann::json loops = nlohmann::json::array();
  for (const BoundaryLoop& loop : chosen.loops) loops.push_back(loop_json(loop, chosen.choice));
  return loops.dump();
}

// The arguments of the fill, as __init__.py checked them.
struct FillArguments {
  std::string mode = "default";
  std::vector<int> ids;
  std::vector<std::array<double, 3>> near;
  int keep_open = -1, max_hole_size = 0;
  double max_hole_diameter = 0;
  std::string method = "foldfill", bending = "quadratic", solver = "fast";
  double lambda = FillOptions{}.energy.lambda, shrink = FillOptions{}.arap.shrink;
  double density = FillOptions{}.triangulate.density;
  double repulsion = FillOptions{}.energy.repulsion;
  double thickness = FillOptions{}.contact.thickness;
  int max_iterations = FillOptions{}.solver.max_iterations;
  int coarse_start = FillOptions{}.multilevel.min_patch_vertices;
  double time_limit = 0;
  std::string obstacles_json;               // {"obstacles": [...]}, or empty
  std::vector<std::string> obstacle_files;  // obstacle files (JSON or prototype text)
  std::vector<std::string> obstacle_mesh_files;
  std::vector<std::pair<py::object, py::object>> obstacle_meshes;  // (vertices, faces)
  std::string source = "mesh";
};

FillRequest request_of(const FillArguments& a) {
  FillRequest request;
  request.source = a.source;
  request.selection = selection_of(a.mode, a.ids, a.near, a.keep_open, a.max_hole_size);
  request.max_hole_diameter_edges = a.max_hole_diameter;
  request.algorithm = a.method == "liepa" ? FillAlgorithm::Liepa : FillAlgorithm::Fabric;
  FillOptions& o = request.options;
  o.energy.lambda = a.lambda;
  o.energy.repulsion = a.repulsion;
  o.energy.bending = a.bending == "two-ring" ? BendingModel::TwoRing : BendingModel::Quadratic;
  o.contact.thickness = a.thickness;
  o.arap.shrink = a.shrink;
  o.triangulate.density = a.density;
  o.solver.kind = a.solver == "gd" ? SolverKind::GradientDescent : SolverKind::Fast;
  o.solver.max_iterations = a.max_iterations;
  o.multilevel.min_patch_vertices = a.coarse_start;
  o.solver.time_limit_seconds = a.time_limit;
  if (!a.obstacles_json.empty()) o.obstacles = parse_obstacles(a.obstacles_json, "obstacles");
  for (const std::string& path : a.obstacle_files) {
    const std::vector<Obstacle> read = read_obstacles(path);
    o.obstacles.insert(o.obstacles.end(), read.begin(), read.end());
  }
  for (const std::string& path : a.obstacle_mesh_files)
    o.obstacles.push_back(read_mesh_obstacle(path));
  for (size_t k = 0; k < a.obstacle_meshes.size(); ++k) {
    const std::string name = "obstacle mesh " + std::to_string(k);
    o.obstacles.push_back(mesh_obstacle(
        mesh_of(a.obstacle_meshes[k].first, a.obstacle_meshes[k].second, name), name));
  }
  return request;
}

// The progress callback of a fill, called from the threads that fill the
// holes with the GIL released: it takes the GIL for each call. An exception
// in the Python callback cancels the fill and is raised again afterwards.
class Progress {
 public:
  explicit Progress(py::object callback) : callback_(std::move(callback)) {}
  ~Progress() {
    py::gil_scoped_acquire gil;
    callback_ = py::object();
    error_ = nullptr;
  }
  bool operator()(int loop_id, const SolverProgress& p) {
    py::gil_scoped_acquire gil;
    if (error_) return false;
    try {
      const py::object answer = callback_(loop_id, p.iteration, p.energy);
      // None (a callback that returns nothing) goes on; False stops.
      return answer.is_none() || answer.cast<bool>();
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
      return false;
    }
  }
  // Raises the callback's exception, if it threw (with the GIL held).
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  py::object callback_;
  std::exception_ptr error_;
  std::mutex mutex_;
};

py::tuple fill_arrays(const py::object& vertices, const py::object& faces,
                      const FillArguments& args, const py::object& progress) {
  const Mesh mesh = mesh_of(vertices, faces, args.source);
  FillRequest request = request_of(args);
  std::unique_ptr<Progress> watcher;
  if (!progress.is_none()) {
    watcher = std::make_unique<Progress>(progress);
    request.options.progress = [&](int id, const SolverProgress& p) { return (*watcher)(id, p); };
  }
  FillOutput result;
  std::string report;
  {
    py::gil_scoped_release release;
    result = foldfill::fill(mesh, request);
    report = report_json(mesh, result, request).dump();
  }
  if (watcher) watcher->rethrow();
  if (result.report.cancelled) {
    PyErr_SetString(cancelled_class, (args.source + ": the fill was cancelled by the progress "
                                                    "callback (the mesh is left as it was)")
                                         .c_str());
    throw py::error_already_set();
  }
  return py::make_tuple(vertices_of(result.mesh), faces_of(result.mesh),
                        marks_of(result.mesh.vertex_hole, result.mesh.positions.size()),
                        marks_of(result.mesh.face_hole, result.mesh.faces.size()), report);
}

// Creates foldfill.NAME with `bases` and the attribute `kind`.
PyObject* make_class(py::module_& m, const char* name, const char* doc, py::tuple bases,
                     const char* kind) {
  const std::string qualified = std::string("foldfill.") + name;
  PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), /*dict=*/nullptr);
  if (!cls) throw py::error_already_set();
  py::handle(cls).attr("kind") = kind;
  m.add_object(name, py::handle(cls));
  return cls;
}

}  // namespace
}  // namespace foldfill::python

PYBIND11_MODULE(_foldfill, m) {
  using namespace foldfill;
  using namespace foldfill::python;
  m.doc() = "foldfill's bindings; use the package `foldfill`, which documents them.";

  // The exception classes mirror the C++ ones (foldfill/error.h): foldfill.Error,
  // InputError for the kinds about a mesh's content, and one subclass per kind.
  // Those about bad arguments or data are ValueErrors too, those about files
  // OSErrors.
  const py::handle value_error(PyExc_ValueError), os_error(PyExc_OSError);
  PyObject* base = make_class(m, "Error", "A foldfill error; `kind` names its category.",
                              py::make_tuple(py::handle(PyExc_Exception)), "error");
  const py::handle b(base);
  const py::handle input(make_class(
      m, "InputError",
      "A mesh foldfill cannot work on: FormatError, NonFiniteCoordinateError, BadFaceError, "
      "NonManifoldError or NotADiskError.",
      py::make_tuple(b, value_error), "input"));
  auto& classes = error_classes();
  classes[ErrorKind::Usage] =
      make_class(m, "UsageError",
                 "Bad arguments: options that contradict each other, an "
                 "unknown loop id, arrays of the wrong shape or type.",
                 py::make_tuple(b, value_error), to_string(ErrorKind::Usage));
  classes[ErrorKind::CannotRead] =
      make_class(m, "ReadError", "A file that cannot be read.", py::make_tuple(b, os_error),
                 to_string(ErrorKind::CannotRead));
  classes[ErrorKind::BadFormat] =
      make_class(m, "FormatError", "A file whose content is not a mesh of its format.",
                 py::make_tuple(input), to_string(ErrorKind::BadFormat));
  classes[ErrorKind::NonFiniteCoordinate] =
      make_class(m, "NonFiniteCoordinateError", "A vertex with a NaN or infinite coordinate.",
                 py::make_tuple(input), to_string(ErrorKind::NonFiniteCoordinate));
  classes[ErrorKind::BadFace] = make_class(
      m, "BadFaceError", "A face with a vertex index out of range, or a repeated vertex.",
      py::make_tuple(input), to_string(ErrorKind::BadFace));
  classes[ErrorKind::NonManifold] =
      make_class(m, "NonManifoldError", "An edge with more than two faces, or a pinched vertex.",
                 py::make_tuple(input), to_string(ErrorKind::NonManifold));
  classes[ErrorKind::NotADisk] =
      make_class(m, "NotADiskError", "A loop named to be filled that is not a disk's boundary.",
                 py::make_tuple(input), to_string(ErrorKind::NotADisk));
  classes[ErrorKind::FillFailed] =
      make_class(m, "FillError", "A stage of the fill could not produce a valid patch.",
                 py::make_tuple(b), to_string(ErrorKind::FillFailed));
  classes[ErrorKind::CannotWrite] =
      make_class(m, "WriteError", "A file that cannot be written.", py::make_tuple(b, os_error),
                 to_string(ErrorKind::CannotWrite));
  classes[ErrorKind::Internal] = make_class(m, "InternalError", "A bug in foldfill.",
                                            py::make_tuple(b), to_string(ErrorKind::Internal));
  cancelled_class = make_class(m, "CancelledError",
                               "The progress callback returned False: the fill was cancelled.",
                               py::make_tuple(b), "cancelled");

  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const Error& e) {
      // Every C++ subclass has one kind, and each kind its Python class.
      PyErr_SetString(error_classes().at(e.kind()), e.what());
    }
  });

  m.def("read", &read_arrays, py::arg("path"), "(vertices, faces, warnings) of a mesh file.");
  m.def("write", &write_arrays, py::arg("path"), py::arg("vertices"), py::arg("faces"),
        py::arg("new_vertices"), py::arg("new_faces"), py::arg("ascii"),
        "Writes a mesh file; the marks may be None.");
  m.def("holes", &list_holes, py::arg("vertices"), py::arg("faces"), py::arg("keep_open"),
        py::arg("source"), "The loops as JSON (`foldfill holes --json`'s \"loops\").");

  py::class_<FillArguments>(m, "FillArguments", "The checked arguments of foldfill.fill.")
      .def(py::init<>())
      .def_readwrite("mode", &FillArguments::mode)
      .def_readwrite("ids", &FillArguments::ids)
      .def_readwrite("near", &FillArguments::near)
      .def_readwrite("keep_open", &FillArguments::keep_open)
      .def_readwrite("max_hole_size", &FillArguments::max_hole_size)
      .def_readwrite("max_hole_diameter", &FillArguments::max_hole_diameter)
      .def_readwrite("method", &FillArguments::method)
      .def_readwrite("bending", &FillArguments::bending)
      .def_readwrite("solver", &FillArguments::solver)
      .def_readwrite("lambda_", &FillArguments::lambda)
      .def_readwrite("shrink", &FillArguments::shrink)
      .def_readwrite("density", &FillArguments::density)
      .def_readwrite("repulsion", &FillArguments::repulsion)
      .def_readwrite("thickness", &FillArguments::thickness)
      .def_readwrite("max_iterations", &FillArguments::max_iterations)
      .def_readwrite("coarse_start", &FillArguments::coarse_start)
      .def_readwrite("time_limit", &FillArguments::time_limit)
      .def_readwrite("obstacles_json", &FillArguments::obstacles_json)
      .def_readwrite("obstacle_files", &FillArguments::obstacle_files)
      .def_readwrite("obstacle_mesh_files", &FillArguments::obstacle_mesh_files)
      .def_readwrite("obstacle_meshes", &FillArguments::obstacle_meshes)
      .def_readwrite("source", &FillArguments::source);
  const FillArguments defaults;
  m.attr("DEFAULT_LAMBDA") = defaults.lambda;
  m.attr("DEFAULT_SHRINK") = defaults.shrink;
  m.attr("DEFAULT_DENSITY") = defaults.density;
  m.attr("DEFAULT_REPULSION") = defaults.repulsion;
  m.attr("DEFAULT_THICKNESS") = defaults.thickness;
  m.attr("DEFAULT_MAX_ITERATIONS") = defaults.max_iterations;
  m.attr("DEFAULT_COARSE_START") = defaults.coarse_start;
  m.def("fill", &fill_arrays, py::arg("vertices"), py::arg("faces"), py::arg("arguments"),
        py::arg("progress"),
        "(vertices, faces, vertex marks, face marks, report JSON) of the filled mesh; the GIL "
        "is released while filling.");
}
