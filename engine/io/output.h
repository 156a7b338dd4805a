#pragma once
// Output of a run: a ParaView series (.pvd indexing one .vtu per frame) and a metrics CSV with one
// row per step. Written by the OutputSystem, which runs only when the scene asks for output.
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "engine/scheduler.h"
#include "engine/world.h"

namespace xcut {

/// Writes the mesh of `world` at its current positions as a VTK UnstructuredGrid (binary appended,
/// zlib; ASCII with output.ascii): point fields displacement_m, velocity_m_per_s, fixed, enriched_dof;
/// cell fields side, parent, volume_fraction, region, material, von_mises_Pa, stress_Pa (Cauchy,
/// 3x3); the units as field data. Each cut element is shown as its two virtual elements, each
/// clipped to its side of the cut (engine/io/clipped_cells.h).
void write_vtu(const World& world, const std::string& path);
/// Writes the visual surface as OBJ (positions [m], triangles; the wound's faces in group "cut") and
/// as a VTK triangle grid with cell fields cut_face (1: the wound's) and mesh_element.
void write_surface_obj(const World& world, const std::string& path);
void write_surface_vtu(const World& world, const std::string& path);
/// Writes the .pvd collection listing (time, file) pairs.
void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& frames);

class OutputWriter {
public:
    explicit OutputWriter(const World& world);
    /// The OutputSystem's work: a frame every `every` steps (step 0 is written at start).
    void frame_if_due(const World& world);
    /// One CSV row, once the step (and its timings) is complete.
    void metrics_row(const World& world);
    void write_frame(const World& world);
    void finish();
    std::string directory() const { return dir_; }

private:
    std::string dir_;
    std::string stem_;
    std::ofstream csv_;
    int split_total_ = 0;        ///< elements split (XFEM or snapping) up to the last row written
    std::vector<std::pair<double, std::string>> frames_;
    std::vector<std::pair<double, std::string>> surface_frames_;
};

/// Prints a one-line progress bar to stderr when it is a terminal and the run lasts over a second.
class ProgressBar {
public:
    ProgressBar(std::string label, int total);
    void update(int done);
    void finish();

private:
    std::string label_;
    int total_;
    bool enabled_;
    double start_;
    int last_percent_ = -1;
};

}  // namespace xcut
