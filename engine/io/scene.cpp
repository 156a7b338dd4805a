#include "engine/io/scene.h"

#include <Eigen/Geometry>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <unordered_set>

#include "engine/error.h"
#include "engine/io/input_file.h"
#include "engine/io/json_fields.h"
#include "engine/io/mesh_io.h"
#include "engine/io/scene_mesh.h"
#include "engine/io/scene_checks.h"
#include "engine/io/scene_grasp.h"
#include "engine/io/scene_node_sets.h"
#include "engine/mesh_repair.h"
#include "engine/setup.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

/// Applies one "a.b.c=value" override; the value is JSON, or a bare string if it does not parse.
void apply_override(nlohmann::json& root, const std::string& file, const std::string& item) {
    const size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError(file, "--set " + item, "expected field.path=value");
    const bool append = item[eq - 1] == '+';  // "tools+={...}": appends to the array
    const std::string path = item.substr(0, append ? eq - 1 : eq), text = item.substr(eq + 1);
    nlohmann::json value = nlohmann::json::parse(text, nullptr, false);
    if (value.is_discarded()) value = text;
    nlohmann::json* at = &root;
    std::stringstream ss(path);
    std::string part;
    while (std::getline(ss, part, '.')) {
        if (at->is_null()) *at = nlohmann::json::object();  // a section the file leaves out
        if (part.empty() || !at->is_object()) throw InputError(file, "--set " + path, "not an object field path");
        at = &(*at)[part];
    }
    if (!append) {
        *at = value;
        return;
    }
    if (at->is_null()) *at = nlohmann::json::array();
    if (!at->is_array()) throw InputError(file, "--set " + path + "+=", "+= appends to an array; this field is not one");
    if (value.is_array())
        for (const auto& v : value) at->push_back(v);
    else
        at->push_back(value);
}

/// A 3D cut polygon must be planar and have area; a 2D segment must have length.
void check_cut_polygon(const JsonFields& c, const std::vector<Eigen::Vector3d>& poly) {
    double size = 0.0;
    for (const auto& p : poly) size = std::max(size, (p - poly[0]).norm());
    if (!(size > 0.0)) c.fail("polygon", "all points coincide");
    if (poly.size() == 2) return;
    Eigen::Vector3d n = Eigen::Vector3d::Zero(), centre = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < poly.size(); ++i) n += poly[i].cross(poly[(i + 1) % poly.size()]), centre += poly[i];
    centre /= static_cast<double>(poly.size());
    if (!(n.norm() > 1e-12 * size * size)) c.fail("polygon", "has zero area (points on one line)");
    n.normalize();
    for (size_t i = 0; i < poly.size(); ++i)
        if (std::abs((poly[i] - centre).dot(n)) > 1e-9 * size)
            c.fail(fmt::format("polygon[{}]", i), "is off the polygon's plane: cut polygons must be planar");
}

/// "orientation": [w, x, y, z] (tool frame -> world), normalized; a zero quaternion is an error.
Eigen::Quaterniond read_quaternion(const JsonFields& k, const nlohmann::json& v, const std::string& field) {
    if (!v.is_array() || v.size() != 4) k.fail(field, fmt::format("expected [w, x, y, z], got {}",
                                                                 v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)));
    double q[4];
    for (int i = 0; i < 4; ++i) {
        if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
            k.fail(fmt::format("{}[{}]", field, i), "expected a finite number");
        q[i] = v[i].get<double>();
    }
    Eigen::Quaterniond out(q[0], q[1], q[2], q[3]);
    if (!(out.norm() > 1e-12)) k.fail(field, "quaternion has zero length");
    return out.normalized();
}

fs::path beside_scene(const fs::path& scene_dir, const std::string& file) {
    const fs::path p = file;
    return (p.is_absolute() ? p : scene_dir / p).lexically_normal();
}

/// "shape": the tool's contact shape in its frame; "contact": its penalty parameters.
void read_tool_shape(const JsonFields& t, const fs::path& scene_dir, ToolBodies& tb) {
    ToolShape shape;
    if (t.has("shape")) {
        const JsonFields sh = t.object("shape");
        const std::string type = sh.choice("type", "", {"sphere", "capsule", "box", "mesh"});
        if (type == "sphere") {
            sh.allow_only({"type", "radius", "centre"});
            shape.kind = ToolShape::kSphere;
            shape.radius = sh.required_number("radius", 1e-6, 1.0);
        } else if (type == "capsule") {
            sh.allow_only({"type", "radius", "length", "centre"});
            shape.kind = ToolShape::kCapsule;
            shape.radius = sh.required_number("radius", 1e-6, 1.0);
            shape.length = sh.required_number("length", 0.0, 10.0);
        } else if (type == "box") {
            sh.allow_only({"type", "size", "centre"});
            shape.kind = ToolShape::kBox;
            shape.half_extent = 0.5 * sh.required_vec3("size");
            if (!(shape.half_extent.minCoeff() > 0.0)) sh.fail("size", "every side must be > 0 [m]");
        } else {
            sh.allow_only({"type", "file"});
            shape.kind = ToolShape::kMesh;
            const ClosedSurface m = read_closed_surface(beside_scene(scene_dir, sh.string("file", "")).string());
            shape.vertices = m.points;
            shape.triangles = m.triangles;
        }
        shape.centre = sh.vec3("centre", Vec3::Zero());
    }
    const JsonFields contact = t.object("contact");
    contact.allow_only({"stiffness", "damping"});
    tb.shape.push_back(shape);
    const double stiffness = contact.number("stiffness", 100.0);
    if (!(stiffness > 0.0)) contact.fail("stiffness", "must be > 0 [N/m]");
    const double damping = contact.number("damping", 0.0);
    if (!(damping >= 0.0)) contact.fail("damping", "must be >= 0 [N s/m]");
    tb.contact_stiffness.push_back(stiffness);
    tb.contact_damping.push_back(damping);
}

/// "tools[i].device": where the tool's pose comes from (engine/devices/device_spec.h).
DeviceSpec read_device(const JsonFields& tool, const std::string& file) {
    DeviceSpec d;
    d.file = file;
    d.field = tool.field("device");
    if (!tool.has("device")) return d;
    const JsonFields dev = tool.object("device");
    dev.allow_only({"type", "host", "port", "stream", "units", "sync", "timeout", "connect_timeout"});
    d.type = dev.choice("type", "scripted", {"scripted", "igtl", "viewer"});
    d.host = dev.string("host", "");
    d.port = dev.integer("port", 18944, 1, 65535);
    d.stream = dev.string("stream", "");
    const std::string units = dev.choice("units", "mm", {"m", "cm", "mm"});
    d.units = units_to_metres(units);
    d.sync = dev.boolean("sync", false);
    d.timeout = dev.number("timeout", 2.0, 1e-3, 3600.0);
    d.connect_timeout = dev.number("connect_timeout", 60.0, 1e-3, 86400.0);
    return d;
}

void read_tools(const JsonFields& top, const fs::path& scene_dir, Scene& scene) {
    const JsonFields cutter = top.object("cutter");
    cutter.allow_only({"threshold", "neighbourhood_depth", "type", "snap_threshold", "front", "tip", "recut"});
    scene.recut = cutter.has("recut") ? (cutter.boolean("recut", false) ? 1 : 0) : -1;
    scene.cut_threshold = cutter.number("threshold", 0.0, 0.0);
    scene.cut_min_depth = cutter.integer("neighbourhood_depth", 1, 0, 50);
    scene.cutter = cutter.choice("type", "xfem", {"xfem", "snap"});
    scene.snap_threshold = cutter.number("snap_threshold", 0.1);
    scene.cut_front = cutter.choice("front", "semi", {"semi", "progressive"});
    if (scene.cut_front == "progressive" && scene.cutter == "snap")
        cutter.fail("front", "\"progressive\" needs \"type\": \"xfem\": snapping splits an element only once it is fully crossed");
    if (cutter.has("tip")) {
        const JsonFields tip = cutter.object("tip");
        tip.allow_only({"radius", "stride"});
        scene.tip_radius = tip.number("radius", 0.0, 0.0);
        scene.tip_stride = tip.number("stride", kTipStrideFraction, 0.0, 1.0);
        if (scene.cutter == "snap") cutter.fail("tip", "crack-tip enrichment is XFEM's: it needs \"type\": \"xfem\"");
        if (scene.cut_front == "progressive")
            cutter.fail("tip", "a tip enriches the element the blade is in, which the \"progressive\" front splits: use "
                               "\"front\": \"semi\"");
    }
    if (!(scene.snap_threshold > 0.0 && scene.snap_threshold < 0.5))
        cutter.fail("snap_threshold", fmt::format("{} is out of range (0, 0.5): a fraction of the crossed edge's length",
                                                  scene.snap_threshold));
    ToolBodies& tb = scene.tools;
    const auto tools = top.array_of_objects("tools", kMaxTools);
    for (size_t i = 0; i < tools.size(); ++i) {
        const JsonFields& t = tools[i];
        t.allow_only({"name", "blade", "shape", "contact", "grasp", "trajectory", "trajectory_csv", "device"});
        tb.name.push_back(t.string("name", fmt::format("tool{}", i)));
        const JsonFields blade = t.object("blade");
        blade.allow_only({"tip", "heel", "back"});
        tb.has_blade.push_back(t.has("blade") ? 1 : 0);
        tb.blade_tip.push_back(blade.vec3("tip", Vec3::Zero()));
        tb.blade_heel.push_back(blade.vec3("heel", Vec3::Zero()));
        if (t.has("blade") && !((tb.blade_heel.back() - tb.blade_tip.back()).norm() > 1e-9))
            blade.fail("heel", "the blade has zero length: tip and heel must differ by more than 1e-9 m");
        tb.blade_back.push_back(blade.vec3("back", Vec3::Zero()));
        if (blade.has("back")) {
            const Vec3 edge = tb.blade_heel.back() - tb.blade_tip.back(), back = tb.blade_back.back();
            if (!(back.norm() > 1e-6) || !(back.norm() <= 1.0))
                blade.fail("back", fmt::format("{:.3g} m long: the blade's width, from its edge to its back, in (1e-6, 1] m",
                                               back.norm()));
            if (!(edge.cross(back).norm() > 0.5 * edge.norm() * back.norm()))
                blade.fail("back", "runs within 30 degrees of the edge (tip to heel): the blade's face would have no width");
        }
        std::vector<Keyframe> keys;
        scene.devices.push_back(read_device(t, top.file()));
        const bool live = scene.devices.back().type != "scripted";
        if (t.has("trajectory") && t.has("trajectory_csv"))
            t.fail("trajectory", "give one of \"trajectory\" (keyframes) or \"trajectory_csv\" (a recorded file), not both");
        if (!live && !t.has("trajectory") && !t.has("trajectory_csv"))
            t.fail("trajectory", "give exactly one of \"trajectory\" (keyframes) or \"trajectory_csv\" (a recorded file)");
        if (live && !t.has("trajectory") && !t.has("trajectory_csv")) keys.push_back(Keyframe{});  // holds at the origin
        read_tool_shape(t, scene_dir, tb);
        read_tool_grasp(t, scene.grasps);
        if (t.has("trajectory_csv")) {
            keys = read_trajectory_csv(beside_scene(scene_dir, t.string("trajectory_csv", "")).string());
        } else {
            const auto frames = t.array_of_objects("trajectory", kMaxTrajectoryRows);
            for (const JsonFields& k : frames) {
                k.allow_only({"time", "position", "orientation"});
                Keyframe key;
                key.time = k.required_number("time");
                key.position = k.required_vec3("position");
                key.orientation = k.has("orientation") ? read_quaternion(k, k.raw("orientation"), "orientation")
                                                       : Eigen::Quaterniond::Identity();
                keys.push_back(key);
            }
        }
        check_trajectory(keys, top.file(), t.field("trajectory"));
        tb.trajectory.push_back(keys);
        tb.position.push_back(keys.front().position);
        tb.orientation.push_back(keys.front().orientation);
    }
}

}  // namespace

void check_trajectory(std::vector<Keyframe>& keys, const std::string& file, const std::string& where) {
    if (keys.empty()) throw InputError(file, where, "needs at least one keyframe");
    for (size_t i = 0; i < keys.size(); ++i) {
        const std::string f = fmt::format("{}[{}]", where, i);
        if (!std::isfinite(keys[i].time)) throw InputError(file, f + ".time", "must be finite");
        if (!keys[i].position.allFinite()) throw InputError(file, f + ".position", "must be finite");
        if (!keys[i].orientation.coeffs().allFinite() || !(keys[i].orientation.norm() > 1e-12))
            throw InputError(file, f + ".orientation", "must be a finite, non-zero quaternion");
        // Unit quaternions are kept bit for bit (a recorded session replays exactly).
        if (std::abs(keys[i].orientation.norm() - 1.0) > 1e-14) keys[i].orientation.normalize();
        if (i > 0 && !(keys[i].time > keys[i - 1].time))
            throw InputError(file, f + ".time",
                             fmt::format("times must increase strictly ({} after {})", keys[i].time, keys[i - 1].time));
    }
}

std::vector<Keyframe> read_trajectory_csv(const std::string& path) {
    std::istringstream in(read_input_file(path, "file", "trajectory", kMaxTrajectoryBytes));
    std::string line;
    std::vector<Keyframe> keys;
    int line_no = 0;
    bool header = false;
    while (std::getline(in, line)) {
        ++line_no;
        if (line.empty() || line[0] == '#') continue;
        if (!header) {
            header = true;
            if (line.rfind("time", 0) == 0) continue;  // header row
        }
        std::stringstream ss(line);
        std::string cell;
        double v[8];
        int n = 0;
        while (std::getline(ss, cell, ',') && n < 9) {
            if (n == 8) throw InputError(path, fmt::format("line {}", line_no), "expected 8 columns: time,x,y,z,qw,qx,qy,qz");
            char* end = nullptr;
            v[n] = std::strtod(cell.c_str(), &end);
            if (end == cell.c_str()) throw InputError(path, fmt::format("line {}", line_no), fmt::format("\"{}\" is not a number", cell));
            ++n;
        }
        if (n != 8) throw InputError(path, fmt::format("line {}", line_no), "expected 8 columns: time,x,y,z,qw,qx,qy,qz");
        if (keys.size() >= kMaxTrajectoryRows)
            throw InputError(path, fmt::format("line {}", line_no),
                             fmt::format("more than {} poses, the limit (2.8 hours at 1 kHz)", kMaxTrajectoryRows));
        Keyframe k;
        k.time = v[0];
        k.position = Vec3(v[1], v[2], v[3]);
        k.orientation = Eigen::Quaterniond(v[4], v[5], v[6], v[7]);
        keys.push_back(k);
    }
    check_trajectory(keys, path, "rows");
    return keys;
}

namespace {

/// The scene's JSON. A key given twice in one object is an error naming its field path (JSON
/// leaves duplicates undefined; nlohmann's parser would silently keep the later one).
/// `path` names the text in messages (a file, or what a scene given as text stands for).
nlohmann::json parse_scene_json(const std::string& text, const std::string& path) {
    struct Container {
        bool object;
        std::string name;                         ///< its field path
        std::unordered_set<std::string> keys;     ///< objects: the keys seen so far
        int next_index = 0;                       ///< arrays: the index of the next element
        std::string key;                          ///< objects: the key of the value being read
    };
    // The stack is bounded by kMaxSceneDepth, so the field paths it keeps (one per level) are too:
    // a file of 200,000 nested arrays is refused at its 65th level, not parsed into gigabytes.
    std::vector<Container> stack;
    const auto child_name = [&stack]() -> std::string {
        if (stack.empty()) return "";
        Container& c = stack.back();
        const std::string sep = c.name.empty() ? "" : ".";
        return c.object ? c.name + sep + c.key : fmt::format("{}[{}]", c.name, c.next_index++);
    };
    using Event = nlohmann::json::parse_event_t;
    const nlohmann::json::parser_callback_t check = [&](int depth, Event event, nlohmann::json& value) {
        if (event == Event::object_start || event == Event::array_start) {
            if (depth >= kMaxSceneDepth)
                throw InputError(path, child_name(),
                                 fmt::format("nested more than {} levels deep (the limit; a scene needs fewer than 8)",
                                             kMaxSceneDepth));
            stack.push_back({event == Event::object_start, child_name(), {}, 0, ""});
        } else if (event == Event::object_end || event == Event::array_end) {
            stack.pop_back();
        } else if (event == Event::key) {
            Container& c = stack.back();
            std::string key = value.get<std::string>();
            if (!c.keys.insert(key).second)
                throw InputError(path, c.name.empty() ? key : c.name + "." + key,
                                 "the key is given twice in one object (JSON keeps only one: remove the other)");
            c.key = std::move(key);
        } else if (event == Event::value && !stack.empty() && !stack.back().object) {
            ++stack.back().next_index;
        }
        return true;
    };
    try {
        return nlohmann::json::parse(text, check, true, /*ignore_comments=*/true);
    } catch (const nlohmann::json::parse_error& e) {
        throw InputError(path, "JSON", fmt::format("not valid JSON (byte {}): {}", e.byte, e.what()));
    } catch (const nlohmann::json::exception& e) {  // out_of_range: a number too large for a double
        throw InputError(path, "JSON", fmt::format("not valid JSON: {}", e.what()));
    }
}

/// The scene in `root`; `path` names it in messages, `dir` is where its relative file names start
/// and `default_name` its name when it gives none.
Scene scene_from_json(nlohmann::json root, const std::string& path, const fs::path& dir,
                      const std::string& default_name, const std::vector<std::string>& overrides) {
    for (const auto& o : overrides) apply_override(root, path, o);

    Scene scene;
    scene.file = path;
    const JsonFields top(root, path, "");
    top.allow_only({"name", "description", "mesh", "material", "region_materials", "bodies", "gravity", "constraints",
                    "solver", "steps", "duration", "output", "cuts", "tools", "cutter", "visual", "collision", "camera",
                    "allow"});
    if (top.has("allow")) {
        const nlohmann::json& allow = top.raw("allow");
        if (!allow.is_array()) top.fail("allow", "expected an array of check names");
        for (size_t i = 0; i < allow.size(); ++i) {
            const std::string item = fmt::format("allow[{}]", i);
            if (!allow[i].is_string()) top.fail(item, "expected a check name");
            const std::string name = allow[i].get<std::string>();
            std::string list;
            bool known = false;
            for (const char* c : kPlausibilityChecks) {
                list += (list.empty() ? "" : ", ") + std::string(c);
                known = known || name == c;
            }
            if (!known) top.fail(item, fmt::format("\"{}\" is not a check (known: {})", name.substr(0, 40), list));
            scene.allow.push_back(name);
        }
    }
    scene.name = top.string("name", default_name);
    // The name is the output's file stem: short, one path component, printable.
    if (scene.name.size() > kMaxSceneNameLength)
        top.fail("name", fmt::format("is {} characters long, above the limit of {} (it names the output files)",
                                     scene.name.size(), kMaxSceneNameLength));
    for (const char ch : scene.name)
        if (ch == '/' || ch == '\\' || static_cast<unsigned char>(ch) < 0x20)
            top.fail("name", "names the output files: no '/', '\\' or control characters");
    if (scene.name.empty() || scene.name == "." || scene.name == "..")
        top.fail("name", "names the output files: give a name other than \"\", \".\" or \"..\"");
    read_bodies(top, dir, scene);

    scene.gravity = top.vec3("gravity", Eigen::Vector3d::Zero());

    const JsonFields con = top.object("constraints");
    con.allow_only({"fixed_boxes", "fixed_nodes", "fixed_sets"});
    scene.fixed_sets = read_fixed_sets(con, dir);
    for (const JsonFields& b : con.array_of_objects("fixed_boxes")) {
        b.allow_only({"min", "max", "axes", "displacement"});
        FixedBox box{b.required_vec3("min"), b.required_vec3("max"), read_axes(b, "axes"),
                     b.vec3("displacement", Eigen::Vector3d::Zero())};
        if ((box.min.array() > box.max.array()).any()) b.fail("max", "every component must be >= min");
        scene.constraints.boxes.push_back(box);
    }
    scene.constraints.nodes = con.int_list("fixed_nodes");

    const JsonFields sol = top.object("solver");
    sol.allow_only({"dt", "mode", "cg_tolerance", "cg_max_iterations", "dt_min", "dt_max", "damping", "newton",
                    "linear", "refactor_iterations", "refactor_every", "renew_delay", "factor_delay", "factor_precision", "max_substeps",
                    "energy_factor", "guess_history"});
    SolverSettings& s = scene.solver;
    s.dt = sol.number("dt", 1e-2, 1e-9, 10.0);
    s.realtime = sol.choice("mode", "fixed", {"fixed", "realtime"}) == "realtime";
    s.cg_tolerance = sol.number("cg_tolerance", 1e-6, 1e-16, 1.0);
    s.cg_max_iterations = sol.integer("cg_max_iterations", 200, 1, 1000000);
    s.dt_min = sol.number("dt_min", 1e-4, 1e-9, 10.0);
    s.dt_max = sol.number("dt_max", 4e-2, s.dt_min, 10.0);
    const JsonFields damp = sol.object("damping");
    damp.allow_only({"mass", "stiffness"});
    s.damping_mass = damp.number("mass", 0.0, 0.0);
    s.damping_stiffness = damp.number("stiffness", 0.0, 0.0);
    const JsonFields newton = sol.object("newton");
    newton.allow_only({"iterations", "tolerance", "on_energy_gain"});
    s.newton_iterations = newton.integer("iterations", 1, 1, 1000);
    s.newton_tolerance = newton.number("tolerance", 1e-6, 1e-16, 1.0);
    s.newton_on_energy_gain = newton.integer("on_energy_gain", s.newton_on_energy_gain, 0, 1000);
    s.linear = sol.choice("linear", "auto", {"auto", "jacobi", "block_jacobi", "amg", "cholesky", "direct"});
    s.refactor_iterations = sol.integer("refactor_iterations", 8, 1, 1000000);
    s.refactor_every = sol.integer("refactor_every", 200, 1, 1000000);
    s.renew_delay = sol.integer("renew_delay", 6, 0, 1000);
    s.factor_delay = sol.integer("factor_delay", 10, 0, 1000);
    s.factor_precision = sol.choice("factor_precision", "auto", {"auto", "double", "single"});
    s.max_substeps = sol.integer("max_substeps", 16, 1, 1024);
    s.guess_history = sol.integer("guess_history", 6, 0, 64);
    s.energy_factor = sol.number("energy_factor", 100.0, 1.0);

    if (top.has("steps") && top.has("duration")) top.fail("duration", "give \"steps\" or \"duration\", not both");
    scene.steps = top.integer("steps", 100, 0, static_cast<int>(kMaxSteps));
    if (top.has("duration")) {
        const double steps = std::ceil(top.required_number("duration", 0.0, 1e6) / s.dt - 1e-9);
        if (steps > static_cast<double>(kMaxSteps))
            top.fail("duration", fmt::format("is {:.3g} steps of solver.dt {:.3g} s, above the limit of {} steps", steps,
                                             s.dt, kMaxSteps));
        scene.steps = static_cast<int>(steps);
    }

    for (const JsonFields& c : top.array_of_objects("cuts", kMaxScriptedCuts)) {
        c.allow_only({"time", "polygon", "frame", "front"});
        ScriptedCut cut;
        cut.time = c.number("time", 0.0, 0.0);
        cut.at_rest = c.choice("frame", "current", {"current", "rest"}) == "rest";
        cut.polygon = c.vec3_list("polygon", 1000);
        if (cut.polygon.size() < 2) c.fail("polygon", "needs 2 points (a segment, 2D) or at least 3 (a planar polygon, 3D)");
        check_cut_polygon(c, cut.polygon);
        if (c.has("front")) {
            const JsonFields front = c.object("front");
            front.allow_only({"radius"});
            cut.front_radius = front.number("radius", 0.0, 0.0);
        }
        scene.cuts.push_back(cut);
    }

    read_tools(top, dir, scene);
    if (top.has("visual")) {
        const JsonFields vis = top.object("visual");
        vis.allow_only({"subdivisions"});
        scene.visual_subdivisions = vis.integer("subdivisions", 0, 0, 3);
    }
    if (top.has("collision")) {
        const JsonFields col = top.object("collision");
        col.allow_only({"subdivisions"});
        scene.collision_subdivisions = col.integer("subdivisions", 0, 0, 3);
    }
    if (top.has("camera")) {
        const JsonFields cam = top.object("camera");
        cam.allow_only({"position", "target", "up", "fov_deg", "width", "height"});
        Camera& c = scene.camera;
        c.automatic = false;
        c.position = cam.required_vec3("position");
        c.target = cam.required_vec3("target");
        c.up = cam.vec3("up", Vec3::UnitY());
        c.fov_deg = cam.number("fov_deg", 40.0, 1.0, 170.0);
        c.width = cam.integer("width", 800, 16, 8192);
        c.height = cam.integer("height", 600, 16, 8192);
        if (!((c.target - c.position).norm() > 0.0)) cam.fail("target", "must differ from position");
        if (!((c.target - c.position).normalized().cross(c.up).norm() > 1e-6)) cam.fail("up", "must not be along the view direction");
    }

    const JsonFields out = top.object("output");
    out.allow_only({"directory", "every", "vtu", "metrics_csv", "format", "max_gb"});
    scene.max_output_gb = out.number("max_gb", kDefaultMaxOutputBytes / 1e9, 1e-6, 1e6);
    scene.output.ascii = out.choice("format", "binary", {"binary", "ascii"}) == "ascii";
    scene.output.directory = out.string("directory", "out/" + scene.name);
    scene.output.name = scene.name;
    scene.output.every = out.integer("every", 10, 1);
    scene.output.vtu = out.boolean("vtu", true);
    scene.output.metrics_csv = out.boolean("metrics_csv", true);
    return scene;
}

/// A quadratic material with crack tips (2D) or fronts (3D), which they do not carry yet
/// (docs/elements.md). Both cutters cut quadratic elements, 2D and 3D.
void refuse_quadratic_where_unsupported(const World& world, const Scene& scene, int dim) {
    if (scene.tip_radius < 0.0) return;
    for (const Material& m : world.materials.list)
        if (m.quadratic)
            throw InputError(scene.file, "material.element",
                             fmt::format("material \"{}\" asks for quadratic elements ({}), which carry no crack {} yet "
                                         "(use \"linear\" with \"cutter.tip\")", m.name,
                                         dim == 3 ? "10-node tetrahedra" : "6-node triangles", dim == 3 ? "fronts" : "tips"));
}

}  // namespace

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
    const std::string text = read_input_file(path, "file", "scene", kMaxSceneBytes);
    return scene_from_json(parse_scene_json(text, path), path, fs::path(path).parent_path(),
                           fs::path(path).stem().string(), overrides);
}

Scene load_scene_text(const std::string& text, const std::string& label, const std::string& base_directory,
                      const std::vector<std::string>& overrides) {
    if (text.size() > kMaxSceneBytes)
        throw InputError(label, "scene", fmt::format("is {} bytes, above the limit of {} bytes", text.size(), kMaxSceneBytes));
    return scene_from_json(parse_scene_json(text, label), label, base_directory, "scene", overrides);
}

World build_world(const Scene& scene) {
    World world;
    world.gravity = scene.gravity;
    world.constraints = scene.constraints;
    world.solver = scene.solver;
    world.output = scene.output;
    SceneBodies bodies = load_scene_bodies(scene);
    const MeshData& mesh = bodies.mesh;
    world.materials.list = bodies.materials;
    // Node indices in a scene count the files' nodes, as the files list them, whatever reading dropped.
    for (size_t i = 0; i < scene.constraints.nodes.size(); ++i)
        world.constraints.nodes[i] = node_of_file_index(bodies, scene.file, fmt::format("constraints.fixed_nodes[{}]", i),
                                                        scene.constraints.nodes[i]);
    if (mesh.dim == 2 && world.gravity.z() != 0.0)
        throw InputError(scene.file, "gravity", "a 2D (plate) scene lies in the xy plane: gravity[2] must be 0");
    for (int i = 0; mesh.dim == 2 && i < scene.tools.count(); ++i)
        if (i < static_cast<int>(scene.tools.blade_back.size()) && scene.tools.blade_back[i] != Vec3::Zero())
            throw InputError(scene.file, fmt::format("tools[{}].blade.back", i),
                             "a 2D scene's blade is a point in the plane: it has no face (give tip and heel only)");
    for (size_t i = 0; i < scene.cuts.size(); ++i) {
        const size_t need = mesh.dim == 2 ? 2 : 3;
        if ((mesh.dim == 2) != (scene.cuts[i].polygon.size() == 2) || scene.cuts[i].polygon.size() < need)
            throw InputError(scene.file, fmt::format("cuts[{}].polygon", i),
                             mesh.dim == 2 ? "a 2D scene is cut by a segment: give exactly 2 points"
                                           : "a 3D scene is cut by a planar polygon: give at least 3 points");
    }
    world.cut_plan.cuts = scene.cuts;
    world.tools = scene.tools;
    world.grasps = scene.grasps;
    for (int i = 0; i < scene.grasps.count(); ++i)
        if (scene.grasps.radius[i] > 0.0 && (scene.cutter == "snap" || (scene.visual_subdivisions < 0 &&
                                                                       scene.collision_subdivisions < 0)))
            throw InputError(scene.file, fmt::format("tools[{}].grasp", i),
                             scene.cutter == "snap"
                                 ? "the jaws hold the tissue's skin, which the snapping cutter builds anew at each split: "
                                   "a grasp needs \"cutter.type\": \"xfem\""
                                 : "the jaws hold the tissue's skin, and this scene has none: give \"visual\" or "
                                   "\"collision\" its \"subdivisions\"");
    world.cut_state.threshold = scene.cut_threshold;
    world.cut_state.min_depth = scene.cut_min_depth;
    world.cut_state.progressive = scene.cut_front == "progressive";
    world.cut_state.recut = static_cast<int8_t>(scene.recut);
    world.snap.enabled = scene.cutter == "snap";
    world.tips.follow_radius = scene.tip_radius;
    world.tips.follow_stride = scene.tip_stride;
    world.snap.threshold = scene.snap_threshold;
    world.snap.visual_subdivisions = scene.visual_subdivisions;
    world.snap.collision_subdivisions = scene.collision_subdivisions;
    world.constraints.sets = resolve_fixed_sets(scene, bodies);
    refuse_quadratic_where_unsupported(world, scene, mesh.dim);
    try {
        build_bodies(world, mesh, bodies.material_of_cell);
    } catch (const std::invalid_argument& e) {  // a quadratic material the mesh cannot take
        throw InputError(scene.file, "material.element", e.what());
    }
    world.elements.body = std::move(bodies.body_of_cell);
    if (scene.recut == 1 && (world.snap.enabled || world.quadratic.count() > 0 || world.tips.follow_radius >= 0.0))
        throw InputError(scene.file, "cutter.recut",
                         "an element is cut again by the XFEM cutter on linear elements without crack tips only: this "
                         "scene has \"type\": \"snap\", quadratic elements or \"tip\"");
    check_cut_fronts(scene, world);
    world.body_names = std::move(bodies.names);
    world.mesh_file_index = std::move(bodies.file_index);
    if (!world.mesh_file_index.empty())  // the mid-edge nodes of quadratic elements are in no file
        world.mesh_file_index.resize(world.mesh_nodes, -1);
    // Several bodies are apart in the mesh: a blade leaving one must find the next by position, not
    // by the crossed elements' neighbours (systems/cut/cut_system.h).
    world.cut_state.bvh_every_quad = world.body_names.size() > 1;
    for (const std::string& note : mesh.notes) world.mesh_notes.push_back(note);
    return world;
}

}  // namespace xcut
