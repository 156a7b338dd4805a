#pragma once
// The per-step figures as named columns: the metrics CSV's header and rows (engine/io/output.h),
// and the Python API's metrics dict, from one list so the two never disagree.
#include <string>
#include <vector>

#include "engine/world.h"

namespace xcut {

struct MetricColumn {
    std::string name;   ///< the CSV header's name, with its unit
    double value = 0.0;
    /// How the CSV prints it: 'd' integer, 'g' 9 significant digits, 'r' 3-digit scientific (a
    /// residual), 'e' 9-digit scientific, 'f' 4 decimals (milliseconds), 's' 6 significant digits.
    char format = 'g';
};

/// The columns after a step, in the CSV's order. The cut columns are there when the scene has tools,
/// the reaction forces when it has shaped tools. `split_total` is the elements split up to the
/// previous row (elements_split counts this step's); it is updated.
std::vector<MetricColumn> metric_columns(const World& world, int& split_total);
/// A column's value as the CSV prints it.
std::string format_metric(const MetricColumn& column);

}  // namespace xcut
