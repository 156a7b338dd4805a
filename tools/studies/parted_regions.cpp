#include "tools/studies/parted_regions.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace xcut {
namespace {

/// Twice the signed area of triangle (a, b, c) (xy).
double orient(const Vec3& a, const Vec3& b, const Vec3& c) {
    return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

/// Whether segments ab and cd cross (each one's ends strictly on both sides of the other's line).
bool segments_cross(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return orient(a, b, c) * orient(a, b, d) < 0.0 && orient(c, d, a) * orient(c, d, b) < 0.0;
}

/// The distance between segments ab and cd (xy), and the two points that realise it (0 where they cross).
double segment_distance(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, Vec3& on_ab, Vec3& on_cd) {
    if (segments_cross(a, b, c, d)) {
        const double s = orient(c, d, a) / (orient(c, d, a) - orient(c, d, b));
        on_ab = on_cd = a + s * (b - a);
        return 0.0;
    }
    double best = std::numeric_limits<double>::infinity();
    const auto consider = [&](const Vec3& p, const Vec3& q) {
        const double l = (p - q).head<2>().norm();
        if (l < best) best = l, on_ab = p, on_cd = q;
    };
    consider(a, nearest_on(c, d, a));
    consider(b, nearest_on(c, d, b));
    consider(nearest_on(a, b, c), c);
    consider(nearest_on(a, b, d), d);
    return best;
}

/// The cells' centres sit this fraction of a cell off the rectangle's grid [-] (an irrational
/// number): a path drawn on round numbers would otherwise pass exactly through centres, where the
/// row and column scans round its crossing to different sides and the boundary leaks.
constexpr double kShift = 0.0707106781186547524;

/// The raster: cells' labels and which neighbour connections a path blocks.
struct Raster {
    Vec3 lo;
    double cell = 0.0;
    int nx = 0, ny = 0;
    std::vector<uint8_t> block_x, block_y;  ///< (i, j)-(i+1, j) and (i, j)-(i, j+1) blocked, at j * nx + i
    std::vector<int> label;

    int at(const Vec3& p) const {
        const int i = std::clamp(static_cast<int>(std::floor((p.x() - lo.x()) / cell - kShift)), 0, nx - 1);
        const int j = std::clamp(static_cast<int>(std::floor((p.y() - lo.y()) / cell - kShift)), 0, ny - 1);
        return label[static_cast<size_t>(j) * nx + i];
    }

    /// Blocks the connections along rows (y = cy(j)) that segment a -> b crosses; `swap` does the
    /// columns with x and y exchanged.
    void block(const Vec3& a, const Vec3& b, bool swap) {
        const auto u = [&](const Vec3& p) { return swap ? p.y() : p.x(); };
        const auto v = [&](const Vec3& p) { return swap ? p.x() : p.y(); };
        const int nu = swap ? ny : nx, nv = swap ? nx : ny;
        const double lu = swap ? lo.y() : lo.x(), lv = swap ? lo.x() : lo.y();
        const double v0 = std::min(v(a), v(b)), v1 = std::max(v(a), v(b));
        // Rows whose centre c satisfies v0 <= c < v1 (a vertex on a row counts with the segment above it).
        const int j0 = std::max(0, static_cast<int>(std::ceil((v0 - lv) / cell - 0.5 - kShift)));
        const int j1 = std::min(nv - 1, static_cast<int>(std::ceil((v1 - lv) / cell - 0.5 - kShift)) - 1);
        for (int j = j0; j <= j1; ++j) {
            const double c = lv + (j + 0.5 + kShift) * cell;
            if (c < v0 || c >= v1) continue;
            const double x = u(a) + (c - v(a)) / (v(b) - v(a)) * (u(b) - u(a));
            const int i = static_cast<int>(std::floor((x - lu) / cell - 0.5 - kShift));  // between centres i and i + 1
            if (i < 0 || i + 1 >= nu) continue;
            (swap ? block_y : block_x)[swap ? static_cast<size_t>(i) * nx + j : static_cast<size_t>(j) * nx + i] = 1;
        }
    }

    /// Labels the connected cells; returns the number of regions.
    int fill() {
        label.assign(static_cast<size_t>(nx) * ny, -1);
        std::vector<int> stack;
        int regions = 0;
        for (size_t start = 0; start < label.size(); ++start) {
            if (label[start] >= 0) continue;
            label[start] = regions;
            stack.push_back(static_cast<int>(start));
            while (!stack.empty()) {
                const int k = stack.back();
                stack.pop_back();
                const int i = k % nx, j = k / nx;
                const auto visit = [&](int n, bool open) {
                    if (open && label[n] < 0) label[n] = regions, stack.push_back(n);
                };
                if (i + 1 < nx) visit(k + 1, !block_x[k]);
                if (i > 0) visit(k - 1, !block_x[k - 1]);
                if (j + 1 < ny) visit(k + nx, !block_y[k]);
                if (j > 0) visit(k - nx, !block_y[k - nx]);
            }
            ++regions;
        }
        return regions;
    }
};

}  // namespace

Vec3 nearest_on(const Vec3& a, const Vec3& b, const Vec3& p) {
    const Eigen::Vector2d u = (b - a).head<2>();
    const double l2 = u.squaredNorm();
    const double t = l2 > 0.0 ? std::clamp(u.dot((p - a).head<2>()) / l2, 0.0, 1.0) : 0.0;
    return a + t * (b - a);
}

PartedRegions parted_regions(const std::vector<std::vector<Vec3>>& paths, const Vec3& lo, const Vec3& hi, double cell) {
    Raster r;
    r.lo = lo, r.cell = cell;
    r.nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / cell - kShift));
    r.ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / cell - kShift));
    if (r.nx < 1 || r.ny < 1 || static_cast<double>(r.nx) * r.ny > double(1 << 24))
        throw std::invalid_argument("parted_regions: the raster must hold 1 to 2^24 cells");
    r.block_x.assign(static_cast<size_t>(r.nx) * r.ny, 0);
    r.block_y.assign(r.block_x.size(), 0);
    for (const auto& p : paths)
        for (size_t k = 1; k < p.size(); ++k) r.block(p[k - 1], p[k], false), r.block(p[k - 1], p[k], true);
    PartedRegions out;
    const int regions = r.fill();
    out.area.assign(regions, 0.0);
    out.boundary.assign(regions, 0.0);
    for (const int l : r.label) out.area[l] += cell * cell;
    // Each segment's two sides, 1.5 cells off its middle.
    for (const auto& p : paths)
        for (size_t k = 1; k < p.size(); ++k) {
            const Eigen::Vector2d d = (p[k] - p[k - 1]).head<2>();
            const double length = d.norm();
            if (length == 0.0) continue;
            const Vec3 mid = 0.5 * (p[k] + p[k - 1]), off = 1.5 * cell * Vec3(-d.y(), d.x(), 0.0) / length;
            const int left = r.at(mid + off), right = r.at(mid - off);
            if (left == right) continue;
            out.boundary[left] += length;
            out.boundary[right] += length;
        }
    return out;
}

double closest_return(const std::vector<Vec3>& p, Vec3& from, Vec3& to) {
    std::vector<double> s(p.size(), 0.0);  // arc length at each point
    for (size_t k = 1; k < p.size(); ++k) s[k] = s[k - 1] + (p[k] - p[k - 1]).head<2>().norm();
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 1; i < p.size(); ++i)
        for (size_t j = i + 1; j < p.size(); ++j) {
            if (s[j - 1] - s[i] <= 0.5 * s.back()) continue;
            Vec3 a = Vec3::Zero(), b = Vec3::Zero();
            const double d = segment_distance(p[i - 1], p[i], p[j - 1], p[j], a, b);
            if (d < best) best = d, from = a, to = b;
        }
    return best;
}

}  // namespace xcut
