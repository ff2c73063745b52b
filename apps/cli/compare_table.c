/* The rows of vorocrust compare's table: what is compared and how each
 * figure is printed, for the text table and the HTML report alike. */
#include "compare.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>

enum {
    ROW_TIME, ROW_CPU, ROW_MEMORY, ROW_VERTICES, ROW_CELLS, ROW_FACES, ROW_BOUNDARY_FACES,
    ROW_VOLUME, ROW_VOLUME_ERROR, ROW_FATNESS_MAX, ROW_FATNESS_MEAN, ROW_FATNESS_P99,
    ROW_EDGE_MIN, ROW_NONORTH_MAX, ROW_NONORTH_MEAN, ROW_SKEW_MAX, ROW_SKEW_FACES, ROW_TRIANGLES,
    ROW_Q_MIN, ROW_Q_MEAN, ROW_BELOW_30, ROW_ABOVE_90, ROW_HAUSDORFF, ROW_COUNT
};

static const char *const row_names[ROW_COUNT] = {
    "time (s)",
    "cpu time (s)",
    "peak memory (MiB)",
    "vertices",
    "cells",
    "faces",
    "boundary faces",
    "total volume",
    "volume error (%)",
    "fatness max",
    "fatness mean",
    "fatness p99",
    "shortest relative edge min",
    "non-orthogonality max (deg)",
    "non-orthogonality average (deg)",
    "skewness max",
    "faces with skewness > 4",
    "surface triangles",
    "surface Q min",
    "surface Q mean",
    "angles < 30 deg (%)",
    "angles > 90 deg (%)",
    "hausdorff / diagonal",
};

int vc_compare_row_count(void)
{
    return ROW_COUNT;
}

const char *vc_compare_row_name(int r)
{
    return r >= 0 && r < ROW_COUNT ? row_names[r] : "";
}

/* A figure that may be missing (NaN: no cell measured, no boundary). */
static void put_number(char *buf, size_t size, const char *fmt, double v)
{
    if (isnan(v))
        snprintf(buf, size, "-");
    else
        snprintf(buf, size, fmt, v);
}

void vc_compare_row_value(const vc_compare *c, int side, int r, char *buf, size_t size)
{
    const vc_compare_side *s = &c->side[side];
    const vc_mesh_report *m = &s->report;
    if (r <= ROW_MEMORY && s->run.started) {
        double v = r == ROW_TIME ? s->run.wall_seconds
                 : r == ROW_CPU  ? s->run.cpu_seconds : s->run.peak_mib;
        snprintf(buf, size, r == ROW_MEMORY ? "%.1f" : "%.3f", v);
        return;
    }
    if (!s->ok) {
        snprintf(buf, size, "failed");
        return;
    }
    switch (r) {
    case ROW_VERTICES: snprintf(buf, size, "%" PRId64, m->n_points); break;
    case ROW_CELLS: snprintf(buf, size, "%" PRId64, m->n_cells); break;
    case ROW_FACES: snprintf(buf, size, "%" PRId64, m->n_faces); break;
    case ROW_BOUNDARY_FACES: snprintf(buf, size, "%" PRId64, m->n_boundary_faces); break;
    case ROW_VOLUME: snprintf(buf, size, "%.10g", m->total_volume); break;
    case ROW_VOLUME_ERROR:
        put_number(buf, size, "%.3g", c->input_volume > 0
                   ? 100.0 * (m->total_volume - c->input_volume) / c->input_volume : NAN);
        break;
    case ROW_FATNESS_MAX: put_number(buf, size, "%.6g", m->fatness.max); break;
    case ROW_FATNESS_MEAN: put_number(buf, size, "%.6g", m->fatness.mean); break;
    case ROW_FATNESS_P99: put_number(buf, size, "%.6g", m->fatness.p99); break;
    case ROW_EDGE_MIN: put_number(buf, size, "%.6g", m->shortest_edge_rel.min); break;
    case ROW_NONORTH_MAX: put_number(buf, size, "%.4g", m->non_orthogonality_max); break;
    case ROW_NONORTH_MEAN: put_number(buf, size, "%.4g", m->non_orthogonality_mean); break;
    case ROW_SKEW_MAX: put_number(buf, size, "%.4g", m->skewness_max); break;
    case ROW_SKEW_FACES: snprintf(buf, size, "%" PRId64, m->n_skew_faces); break;
    case ROW_TRIANGLES: snprintf(buf, size, "%" PRId64, m->n_boundary_triangles); break;
    case ROW_Q_MIN: put_number(buf, size, "%.6g", m->triangle_quality.min); break;
    case ROW_Q_MEAN: put_number(buf, size, "%.6g", m->triangle_quality.mean); break;
    case ROW_BELOW_30: put_number(buf, size, "%.2f", m->angles_below_30); break;
    case ROW_ABOVE_90: put_number(buf, size, "%.2f", m->angles_above_90); break;
    case ROW_HAUSDORFF:
        put_number(buf, size, "%.4g", m->has_hausdorff ? m->hausdorff.normalised : NAN);
        break;
    default: snprintf(buf, size, "-"); break;
    }
}
