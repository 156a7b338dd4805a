// The compiled part of the Python package (import xcut; tools/python/xcut/__init__.py wraps it):
// PySimulation bound with pybind11, its state handed over as numpy arrays that own their memory
// (copies, see docs/python.md), xcut's errors raised as xcut.InputError (a ValueError, with .file
// and .field) and xcut.NumericalError (a RuntimeError). step() releases the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <mutex>

#include "engine/error.h"
#include "engine/io/output.h"
#include "engine/io/scene_checks.h"
#include "engine/parallel.h"
#include "tools/python/py_simulation.h"
#include "tools/xcut_run_summary.h"

namespace py = pybind11;
using xcut::PySimulation;

namespace {

/// A read-only numpy array that owns `values` (moved into it, no copy).
template <class T>
py::array owned(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
    auto* held = new std::vector<T>(std::move(values));
    py::capsule free(held, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    py::array_t<T> a(shape, held->data(), free);
    a.attr("flags").attr("writeable") = false;
    return a;
}

py::array rows3(std::vector<double>&& v) {
    const py::ssize_t n = static_cast<py::ssize_t>(v.size() / 3);
    return owned(std::move(v), {n, 3});
}

py::dict surface_dict(xcut::PySurface&& s) {
    const py::ssize_t t = static_cast<py::ssize_t>(s.cut_face.size());
    py::dict d;
    d["vertices"] = rows3(std::move(s.vertices));
    d["triangles"] = owned(std::move(s.triangles), {t, 3});
    d["cut_face"] = owned(std::move(s.cut_face), {t});
    return d;
}

using Lock = std::lock_guard<std::mutex>;

void bind_state(py::class_<PySimulation>& c) {
    c.def("positions", [](PySimulation& s, bool all) { Lock l(s.mutex()); return rows3(s.positions(all)); },
          py::arg("all_dofs") = false);
    c.def("velocities", [](PySimulation& s, bool all) { Lock l(s.mutex()); return rows3(s.velocities(all)); },
          py::arg("all_dofs") = false);
    c.def("rest_positions", [](PySimulation& s) { Lock l(s.mutex()); return rows3(s.rest_positions()); });
    c.def("elements", [](PySimulation& s) {
        Lock l(s.mutex());
        std::vector<int> e = s.mesh_elements();
        const py::ssize_t per = s.world().elements.dim + 1;
        const py::ssize_t n = static_cast<py::ssize_t>(e.size()) / per;
        return owned(std::move(e), {n, per});
    });
    c.def("von_mises", [](PySimulation& s) {
        Lock l(s.mutex());
        std::vector<double> v = s.von_mises();
        const py::ssize_t n = static_cast<py::ssize_t>(v.size());
        return owned(std::move(v), {n});
    });
    c.def("cut_state", [](PySimulation& s) {
        Lock l(s.mutex());
        std::vector<int> cut = s.cut_elements(), nodes = s.enriched_nodes();
        std::vector<double> open = s.openings(nodes);
        py::dict d;
        d["elements_split"] = cut.size();
        const py::ssize_t nc = static_cast<py::ssize_t>(cut.size()), nn = static_cast<py::ssize_t>(nodes.size());
        d["cut_elements"] = owned(std::move(cut), {nc});
        d["enriched_nodes"] = owned(std::move(nodes), {nn});
        d["opening_m"] = owned(std::move(open), {nn});
        // The pieces of tissue, slivers left out (components/pieces.h).
        const xcut::Pieces& p = s.world().pieces;
        std::vector<double> volume;
        std::vector<uint8_t> anchored;
        for (size_t k = 0; k < p.volume.size(); ++k)
            if (!p.sliver[k]) volume.push_back(p.volume[k]), anchored.push_back(p.anchored[k]);
        const py::ssize_t np = static_cast<py::ssize_t>(volume.size());
        d["pieces"] = np;
        d["piece_volume_m3"] = owned(std::move(volume), {np});
        d["piece_anchored"] = owned(std::move(anchored), {np});
        return d;
    });
    c.def("surface", [](PySimulation& s, bool collision) { Lock l(s.mutex()); return surface_dict(s.surface(collision)); },
          py::arg("collision") = false);
}

void bind_tools(py::class_<PySimulation>& c) {
    c.def("tool_names", [](PySimulation& s) { Lock l(s.mutex()); return s.world().tools.name; });
    c.def("tool_index", [](PySimulation& s, const std::string& n) { Lock l(s.mutex()); return s.tool_index(n); });
    c.def("tool_pose", [](PySimulation& s, int i) {
        Lock l(s.mutex());
        if (i < 0 || i >= s.world().tools.count()) throw py::index_error("no such tool");
        const xcut::ToolBodies& tb = s.world().tools;
        const Eigen::Quaterniond& q = tb.orientation[i];
        return py::make_tuple(owned(std::vector<double>(tb.position[i].data(), tb.position[i].data() + 3), {3}),
                              owned(std::vector<double>{q.w(), q.x(), q.y(), q.z()}, {4}));
    });
    c.def("set_tool_pose", [](PySimulation& s, int i, std::array<double, 3> p, std::array<double, 4> q) {
        Lock l(s.mutex());
        s.set_tool_pose(i, xcut::Vec3(p[0], p[1], p[2]), Eigen::Quaterniond(q[0], q[1], q[2], q[3]));
    });
    c.def("tool_driven", [](PySimulation& s, int i) { Lock l(s.mutex()); return s.tool_driven(i); });
    c.def("tool_force", [](PySimulation& s, int i) {
        Lock l(s.mutex());
        const xcut::ToolBodies& tb = s.world().tools;
        if (i < 0 || i >= tb.count()) throw py::index_error("no such tool");
        const bool known = i < static_cast<int>(tb.reaction_force.size());
        const xcut::Vec3 f = known ? tb.reaction_force[i] : xcut::Vec3::Zero();
        const xcut::Vec3 t = known ? tb.reaction_torque[i] : xcut::Vec3::Zero();
        return py::make_tuple(owned(std::vector<double>{f.x(), f.y(), f.z()}, {3}),
                              owned(std::vector<double>{t.x(), t.y(), t.z()}, {3}));
    });
}

void bind_simulation(py::module_& m) {
    py::class_<PySimulation> c(m, "_Simulation");
    c.def(py::init([](const std::string& path, const std::string& text, const std::string& base,
                      const std::vector<std::string>& overrides, const std::string& output) {
              py::gil_scoped_release release;  // building a large mesh takes a while
              return std::make_unique<PySimulation>(xcut::PySceneSource{path, text, base, overrides}, output);
          }),
          py::arg("path"), py::arg("text"), py::arg("base_directory"), py::arg("overrides"), py::arg("output"));
    c.def("step", [](PySimulation& s, int n) {
        if (n < 0) throw py::value_error("n must be >= 0");
        py::gil_scoped_release release;
        Lock l(s.mutex());
        s.step(n);
    });
    c.def_property_readonly("time", [](PySimulation& s) { Lock l(s.mutex()); return s.world().time; });
    c.def_property_readonly("dt", [](PySimulation& s) { Lock l(s.mutex()); return s.world().solver.dt; });
    c.def_property_readonly("step_count", [](PySimulation& s) { Lock l(s.mutex()); return s.steps_done(); });
    c.def_property_readonly("scene_steps", [](PySimulation& s) { return s.scene().steps; });
    c.def_property_readonly("name", [](PySimulation& s) { return s.scene().name; });
    c.def_property_readonly("dim", [](PySimulation& s) { return s.world().elements.dim; });
    c.def_property_readonly("failed", [](PySimulation& s) { return s.failed(); });
    c.def_property_readonly("warnings", [](PySimulation& s) { return s.warnings(); });
    c.def_property_readonly("notes", [](PySimulation& s) { Lock l(s.mutex()); return xcut::end_of_run_notes(s.world()); });
    c.def("metrics", [](PySimulation& s) {
        Lock l(s.mutex());
        py::dict d;
        for (const xcut::MetricColumn& col : s.metrics()) {
            if (col.format == 'd') d[py::str(col.name)] = static_cast<long long>(col.value);
            else d[py::str(col.name)] = col.value;
        }
        return d;
    });
    c.def("figures_json", [](PySimulation& s, double wall) {
        Lock l(s.mutex());
        return xcut::figures_json(xcut::run_figures(s.world(), s.steps_done(), wall)).dump();
    });
    c.def("write_vtu", [](PySimulation& s, const std::string& p) { Lock l(s.mutex()); xcut::write_vtu(s.world(), p); });
    c.def("write_surface_obj", [](PySimulation& s, const std::string& p) {
        Lock l(s.mutex());
        xcut::write_surface_obj(s.world(), p);
    });
    bind_state(c);
    bind_tools(c);
}

/// Raises xcut.InputError with .file, .field and .message, the text the CLI prints after "error: ".
void register_errors(py::module_& m) {
    static py::exception<xcut::InputError> input(m, "InputError", PyExc_ValueError);
    static py::exception<xcut::NumericalError> numerical(m, "NumericalError", PyExc_RuntimeError);
    input.attr("__module__") = "xcut", numerical.attr("__module__") = "xcut";  // raised as xcut.InputError
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const xcut::InputError& e) {
            py::object err = py::reinterpret_borrow<py::object>(input.ptr())(e.what());
            err.attr("file") = e.file(), err.attr("field") = e.field(), err.attr("message") = e.message();
            PyErr_SetObject(input.ptr(), err.ptr());
        } catch (const xcut::NumericalError& e) {
            numerical(e.what());
        }
    });
}

}  // namespace

PYBIND11_MODULE(_xcut, m) {
    m.doc() = "xcut's compiled core: use the xcut package (xcut.Simulation), not this module.";
    register_errors(m);
    bind_simulation(m);
    m.def("set_threads", [](int n) { xcut::set_thread_count(n); }, "Threads the engine uses (process-wide).");
    m.def("threads", [] { return xcut::configured_thread_count(); });
}
