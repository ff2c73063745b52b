/* The HTML report of vorocrust compare: one self-contained page (inline
 * CSS, no script, no external resource) with the comparison table, the
 * commands, and two histograms drawn as inline SVG, cell fatness and
 * boundary triangle quality, both meshers side by side in every bin as a
 * percentage of their own cells or triangles (the counts differ). Every bar
 * carries its count (data-count) and a tooltip (title). */
#include "compare.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/io.h"
#include "io/tmpfile.h"

#define MAX_BINS 64
#define SVG_WIDTH 1000
#define SVG_HEIGHT 360
#define PLOT_LEFT 64
#define PLOT_RIGHT 16
#define PLOT_TOP 56 /* the title, then the legend on its own line */
#define PLOT_BOTTOM 52
#define CUT_SIZE 480 /* each mesh's cut, in SVG units */
/* a volume further off the input's than this is flagged */
#define VOLUME_FLAG_PERCENT 0.5

static const char *const side_colour[VC_COMPARE_SIDES] = {"#1f6fb4", "#e08a1e"};

/* Counts per bin: bins of equal width over [lo, hi); with overflow, one
 * more bin for the values >= hi. Values below lo go to the first bin, NaN
 * values are not counted. */
typedef struct histogram {
    const char *title;     /* "cell fatness" */
    const char *quantity;  /* "fatness", for tooltips */
    const char *items;     /* "cells" */
    double lo, hi;
    int bins;              /* equal-width bins, overflow excluded */
    int overflow;
    int64_t count[VC_COMPARE_SIDES][MAX_BINS + 1];
    int64_t total[VC_COMPARE_SIDES];
} histogram;

static void histogram_add(histogram *h, int side, const double *v, int64_t n)
{
    for (int64_t i = 0; i < n; i++) {
        if (isnan(v[i]))
            continue;
        int b;
        if (v[i] >= h->hi)
            b = h->overflow ? h->bins : h->bins - 1;
        else if (v[i] <= h->lo)
            b = 0;
        else
            b = (int)((v[i] - h->lo) / (h->hi - h->lo) * h->bins);
        b = b < 0 ? 0 : b > h->bins ? h->bins : b;
        if (b == h->bins && !h->overflow)
            b = h->bins - 1;
        h->count[side][b]++;
        h->total[side]++;
    }
}

static void put_escaped(FILE *fp, const char *s)
{
    for (; *s; s++) {
        switch (*s) {
        case '&': fputs("&amp;", fp); break;
        case '<': fputs("&lt;", fp); break;
        case '>': fputs("&gt;", fp); break;
        case '"': fputs("&quot;", fp); break;
        default: fputc(*s, fp);
        }
    }
}

/* A round number at least x: 1, 2 or 5 times a power of ten. */
static double round_up(double x)
{
    if (!(x > 0))
        return 1;
    double p = pow(10, floor(log10(x)));
    return x <= p ? p : x <= 2 * p ? 2 * p : x <= 5 * p ? 5 * p : 10 * p;
}

static void bin_range(const histogram *h, int b, double *lo, double *hi)
{
    double w = (h->hi - h->lo) / h->bins;
    *lo = h->lo + b * w;
    *hi = b < h->bins ? h->lo + (b + 1) * w : INFINITY;
}

static void write_svg(FILE *fp, const vc_compare *c, const histogram *h, const char *id)
{
    const int nb = h->bins + h->overflow;
    const double pw = SVG_WIDTH - PLOT_LEFT - PLOT_RIGHT, ph = SVG_HEIGHT - PLOT_TOP - PLOT_BOTTOM;
    double ymax = 0;
    for (int s = 0; s < VC_COMPARE_SIDES; s++)
        for (int b = 0; b < nb && h->total[s]; b++) {
            double pct = 100.0 * (double)h->count[s][b] / (double)h->total[s];
            ymax = pct > ymax ? pct : ymax;
        }
    /* the axis ends at a multiple of a round step, at most 5 steps */
    const double ystep = round_up(ymax / 5);
    const int nsteps = ymax > 0 ? (int)ceil(ymax / ystep - 1e-9) : 1;
    ymax = ystep * nsteps;
    fprintf(fp, "<svg id=\"%s\" xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
            "viewBox=\"0 0 %d %d\" role=\"img\">\n", id, SVG_WIDTH, SVG_HEIGHT, SVG_WIDTH, SVG_HEIGHT);
    fprintf(fp, "<text x=\"%d\" y=\"20\" class=\"title\">%s (percent of each mesher's %s)</text>\n",
            PLOT_LEFT, h->title, h->items);
    /* legend, under the title */
    for (int s = 0; s < VC_COMPARE_SIDES; s++) {
        int x = PLOT_LEFT + 160 * s;
        fprintf(fp, "<rect x=\"%d\" y=\"28\" width=\"12\" height=\"12\" fill=\"%s\"/>"
                "<text x=\"%d\" y=\"39\">%s%s</text>\n", x, side_colour[s], x + 16,
                c->side[s].name, c->side[s].ok ? "" : " (failed)");
    }
    /* y grid and labels */
    for (int k = 0; k <= nsteps; k++) {
        double y = PLOT_TOP + ph - ph * k / nsteps;
        fprintf(fp, "<line x1=\"%d\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" class=\"grid\"/>"
                "<text x=\"%d\" y=\"%.1f\" text-anchor=\"end\">%g%%</text>\n", PLOT_LEFT, y,
                PLOT_LEFT + pw, y, PLOT_LEFT - 6, y + 4, ystep * k);
    }
    /* bars: two per bin */
    const double bw = pw / nb;
    for (int b = 0; b < nb; b++) {
        double lo, hi;
        bin_range(h, b, &lo, &hi);
        for (int s = 0; s < VC_COMPARE_SIDES; s++) {
            if (!h->total[s])
                continue;
            double pct = 100.0 * (double)h->count[s][b] / (double)h->total[s];
            double height = ph * pct / ymax;
            double x = PLOT_LEFT + b * bw + bw * (0.1 + 0.4 * s);
            fprintf(fp, "<rect class=\"bar\" data-mesher=\"%s\" data-count=\"%" PRId64 "\" "
                    "data-lo=\"%.6g\" data-hi=\"%.6g\" x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" "
                    "height=\"%.2f\" fill=\"%s\"><title>%s: %" PRId64 " %s (%.2f%%) with %s in ",
                    c->side[s].name, h->count[s][b], lo, hi, x, PLOT_TOP + ph - height, bw * 0.4,
                    height, side_colour[s], c->side[s].name, h->count[s][b], h->items, pct,
                    h->quantity);
            if (isinf(hi))
                fprintf(fp, "[%.4g, infinity)</title></rect>\n", lo);
            else
                fprintf(fp, "[%.4g, %.4g%s</title></rect>\n", lo, hi,
                        b == nb - 1 && !h->overflow ? "]" : ")");
        }
    }
    /* x axis: a label every few bins */
    fprintf(fp, "<line x1=\"%d\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" class=\"axis\"/>\n",
            PLOT_LEFT, PLOT_TOP + ph, PLOT_LEFT + pw, PLOT_TOP + ph);
    int step = h->bins <= 10 ? 1 : h->bins <= 20 ? 2 : h->bins <= 40 ? 5 : 10;
    for (int b = 0; b <= h->bins; b += step) {
        double lo, hi;
        bin_range(h, b, &lo, &hi);
        double x = PLOT_LEFT + b * bw;
        fprintf(fp, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%g</text>\n", x,
                PLOT_TOP + ph + 16, lo);
    }
    if (h->overflow)
        fprintf(fp, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">&#8805;%g</text>\n",
                PLOT_LEFT + (h->bins + 0.5) * bw, PLOT_TOP + ph + 30, h->hi);
    fprintf(fp, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%s</text>\n",
            PLOT_LEFT + pw / 2, SVG_HEIGHT - 6, h->quantity);
    fputs("</svg>\n", fp);
}

/* Fatness is at least 1 (the inscribed ball fits in the enclosing one).
 * The bins reach one and a half times the smaller p99 of the two meshes,
 * the rest overflows into the last bar: with the larger one, a mesher
 * whose cells are much fatter would squeeze the other's distribution
 * into a few bars. */
static void fatness_histogram(const vc_compare *c, histogram *h)
{
    memset(h, 0, sizeof *h);
    h->title = "Cell fatness";
    h->quantity = "fatness (enclosing / inscribed ball radius)";
    h->items = "cells";
    double top = INFINITY;
    for (int s = 0; s < VC_COMPARE_SIDES; s++)
        if (c->side[s].ok && c->side[s].report.fatness.n)
            top = fmin(top, c->side[s].report.fatness.p99);
    top = isfinite(top) ? fmax(2, 1.5 * top) : 3;
    /* about 40 bins of a round width (0.05, 0.1, 0.2, 0.25, 0.5, ...) */
    h->lo = 1;
    const double want = (top - 1) / 40;
    const double mag = pow(10, floor(log10(want)));
    static const double steps[] = {1, 2, 2.5, 5, 10};
    double w = 10 * mag;
    for (int k = 0; k < 5; k++)
        if (steps[k] * mag >= want) {
            w = steps[k] * mag;
            break;
        }
    h->bins = (int)ceil((top - 1) / w - 1e-9);
    h->bins = h->bins > MAX_BINS ? MAX_BINS : h->bins < 4 ? 4 : h->bins;
    h->hi = h->lo + h->bins * w;
    h->overflow = 1;
    for (int s = 0; s < VC_COMPARE_SIDES; s++)
        if (c->side[s].ok)
            histogram_add(h, s, c->side[s].report.cell_fatness, c->side[s].report.n_cells);
}

static void quality_histogram(const vc_compare *c, histogram *h)
{
    memset(h, 0, sizeof *h);
    h->title = "Boundary triangle quality";
    h->quantity = "Q = 6S / (sqrt(3) h P)";
    h->items = "boundary triangles";
    h->lo = 0;
    h->hi = 1;
    h->bins = 20;
    h->overflow = 0;
    for (int s = 0; s < VC_COMPARE_SIDES; s++)
        if (c->side[s].ok)
            histogram_add(h, s, c->side[s].report.triangle_qualities,
                          c->side[s].report.n_boundary_triangles);
}

/* A side's volume error in percent (NaN when unknown). */
static double volume_error(const vc_compare *c, int s)
{
    const vc_compare_side *sd = &c->side[s];
    return sd->ok && c->input_volume > 0
               ? 100.0 * (sd->report.total_volume - c->input_volume) / c->input_volume
               : NAN;
}

/* A command, its temporary directory written TMP (it is gone after the run). */
static void put_command(FILE *fp, const vc_compare *c, const char *cmd)
{
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", cmd);
    if (c->work_dir && c->work_dir[0]) {
        const size_t n = strlen(c->work_dir);
        char out[4096];
        size_t k = 0;
        for (const char *p = buf; *p && k + 4 < sizeof out;) {
            if (!strncmp(p, c->work_dir, n)) {
                memcpy(out + k, "TMP", 3);
                k += 3;
                p += n;
            } else {
                out[k++] = *p++;
            }
        }
        out[k] = 0;
        put_escaped(fp, out);
        return;
    }
    put_escaped(fp, buf);
}

/* Each mesh cut by the plane through the middle of the input's box, across
 * its smallest extent: the cells' faces where the plane crosses them. */
static void write_cuts(FILE *fp, const vc_compare *c)
{
    static const char axis_name[3] = {'x', 'y', 'z'};
    const int a = c->cut_axis, u = (a + 1) % 3, v = (a + 2) % 3;
    const double w = c->bbox[u + 3] - c->bbox[u], h = c->bbox[v + 3] - c->bbox[v];
    const double scale = CUT_SIZE / fmax(w, h > 0 ? h : w);
    const double W = w * scale, H = h * scale;
    fprintf(fp, "<h2>The meshes cut at %c = %.6g</h2>\n<div class=\"cuts\">\n", axis_name[a],
            c->cut_value);
    for (int s = 0; s < VC_COMPARE_SIDES; s++) {
        const vc_compare_side *sd = &c->side[s];
        fprintf(fp, "<figure><svg id=\"cut-%s\" xmlns=\"http://www.w3.org/2000/svg\" "
                "viewBox=\"-4 -4 %.0f %.0f\" role=\"img\"><g stroke=\"%s\" stroke-width=\"0.5\" "
                "fill=\"none\">\n", sd->name, W + 8, H + 8, side_colour[s]);
        for (int64_t i = 0; sd->ok && i < sd->n_cut; i++) {
            const double *q = sd->cut + 4 * i;
            /* y up: SVG's y runs down */
            fprintf(fp, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n",
                    (q[0] - c->bbox[u]) * scale, H - (q[1] - c->bbox[v]) * scale,
                    (q[2] - c->bbox[u]) * scale, H - (q[3] - c->bbox[v]) * scale);
        }
        fprintf(fp, "</g></svg><figcaption>%s: %s%s (%c right, %c up)</figcaption></figure>\n",
                sd->name, sd->ok ? "" : "failed", sd->ok ? "cells cut" : "", axis_name[u],
                axis_name[v]);
    }
    fputs("</div>\n", fp);
}

static void write_page(FILE *fp, const vc_compare *c)
{
    fputs("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>"
          "vorocrust compare: ", fp);
    put_escaped(fp, c->input);
    fputs("</title>\n<style>\n"
          "body { font-family: sans-serif; margin: 2em; color: #222; }\n"
          "table { border-collapse: collapse; margin: 1em 0; }\n"
          "th, td { border: 1px solid #bbb; padding: 0.25em 0.8em; }\n"
          "td.num { text-align: right; font-variant-numeric: tabular-nums; }\n"
          "td.failed { color: #b00; font-weight: bold; text-align: center; }\n"
          "code { background: #f3f3f3; padding: 0.1em 0.3em; }\n"
          "svg { display: block; margin: 1em 0; font-size: 12px; width: 100%; max-width: 1100px; "
          "height: auto; }\n"
          "div.cuts { display: flex; gap: 2%; max-width: 1100px; }\n"
          "div.cuts figure { flex: 1; margin: 0; } div.cuts svg { border: 1px solid #ccc; }\n"
          "td.flag { color: #b00; font-weight: bold; } p.flag { color: #b00; }\n"
          "svg .title { font-size: 14px; font-weight: bold; }\n"
          "svg .grid { stroke: #ddd; } svg .axis { stroke: #444; }\n"
          "</style>\n</head>\n<body>\n<h1>vorocrust compare</h1>\n<p>Input <code>", fp);
    put_escaped(fp, c->input);
    fprintf(fp, "</code>: %" PRId64 " triangles, enclosed volume %.10g, bounding-box diagonal "
            "%.6g.</p>\n", c->input_triangles, c->input_volume, c->input_diagonal);
    fprintf(fp, "<p>Run %s: vorocrust %s with %d thread%s; TetGen through vc-tetgen (Debian's "
            "libtet1.5, one thread).</p>\n", c->date, c->version, c->threads,
            c->threads == 1 ? "" : "s");
    for (int s = 0; s < VC_COMPARE_SIDES; s++)
        if (!c->side[s].ok) {
            fprintf(fp, "<p class=\"failure\"><strong>%s failed:</strong> ", c->side[s].name);
            put_escaped(fp, c->side[s].failure);
            fputs("</p>\n", fp);
        }
    /* what a reader must not miss */
    for (int s = 0; s < VC_COMPARE_SIDES; s++) {
        const vc_compare_side *sd = &c->side[s];
        if (sd->resampled) {
            fprintf(fp, "<p class=\"flag\"><strong>%s sampled the surface twice</strong> (the "
                    "first sampling diverged): ", sd->name);
            put_escaped(fp, sd->resample_note);
            fputs("</p>\n", fp);
        }
        const double err = volume_error(c, s);
        if (fabs(err) > VOLUME_FLAG_PERCENT)
            fprintf(fp, "<p class=\"flag\"><strong>%s's volume is off the input's by %+.2f%%"
                    "</strong> (more than %g%%).</p>\n", sd->name, err, VOLUME_FLAG_PERCENT);
    }
    fputs("<table id=\"comparison\">\n<tr><th>metric</th>", fp);
    for (int s = 0; s < VC_COMPARE_SIDES; s++)
        fprintf(fp, "<th>%s</th>", c->side[s].name);
    fputs("</tr>\n", fp);
    for (int r = 0; r < vc_compare_row_count(); r++) {
        fputs("<tr><td>", fp);
        put_escaped(fp, vc_compare_row_name(r));
        fputs("</td>", fp);
        for (int s = 0; s < VC_COMPARE_SIDES; s++) {
            char v[64];
            vc_compare_row_value(c, s, r, v, sizeof v);
            const int flagged = !strcmp(vc_compare_row_name(r), "volume error (%)") &&
                                fabs(volume_error(c, s)) > VOLUME_FLAG_PERCENT;
            fprintf(fp, "<td class=\"%s\">", !strcmp(v, "failed") ? "failed"
                                               : flagged ? "num flag" : "num");
            put_escaped(fp, v);
            fputs("</td>", fp);
        }
        fputs("</tr>\n", fp);
    }
    fputs("</table>\n<p>Time: wall-clock seconds of the whole mesher process (reading, meshing, "
          "writing the .vtu); peak memory: its maximum resident set size. Fatness: smallest "
          "enclosing ball radius over largest inscribed ball radius (1.73 for a cube, 3 for a "
          "regular tetrahedron). Surface: the boundary faces, polygons fanned from their vertex "
          "average; Q = 1 for an equilateral triangle. Hausdorff: two-sided distance between the "
          "mesh boundary and the input over the input's bounding-box diagonal.</p>\n<ul>\n", fp);
    for (int s = 0; s < VC_COMPARE_SIDES; s++) {
        fprintf(fp, "<li>%s: <code>", c->side[s].name);
        put_command(fp, c, c->side[s].command);
        fputs("</code>", fp);
        if (c->side[s].phases[0]) {
            fputs("<br>its phases (s): ", fp);
            put_escaped(fp, c->side[s].phases);
        }
        fputs("</li>\n", fp);
    }
    if (c->tetgen_target) {
        fprintf(fp, "<li>tetgen's volume bound, for about %" PRId64 " cells (vorocrust's count "
                "unless --target-cells was given): <code>", c->tetgen_target);
        put_command(fp, c, c->tetgen_bound_command);
        fputs("</code></li>\n", fp);
    }
    fputs("</ul>\n", fp);
    if (c->work_dir)
        fputs("<p>TMP: a temporary directory, removed after the run (--mesh-dir keeps the "
              "meshes).</p>\n", fp);
    write_cuts(fp, c);
    histogram h;
    fatness_histogram(c, &h);
    write_svg(fp, c, &h, "fatness-histogram");
    quality_histogram(c, &h);
    write_svg(fp, c, &h, "quality-histogram");
    fputs("</body>\n</html>\n", fp);
}

int vc_compare_write_html(const vc_compare *c, const char *path, vc_error *err)
{
    vc_tmpfile t;
    int rc = vc_tmpfile_open(&t, path, err);
    if (rc)
        return rc;
    write_page(t.fp, c);
    if (ferror((FILE *)t.fp)) {
        vc_tmpfile_discard(&t);
        return vc_error_set(err, VC_EIO, "%s: cannot write", path);
    }
    return vc_tmpfile_commit(&t, err);
}
