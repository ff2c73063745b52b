/* vorocrust compare: the two meshers' results on one input, and the rows
 * of the comparison table shared by the text table and the HTML report. */
#ifndef VC_CLI_COMPARE_H
#define VC_CLI_COMPARE_H

#include <stddef.h>
#include <stdint.h>

#include "child_process.h"
#include "vorocrust/error.h"
#include "vorocrust/mesh_report.h"

enum { VC_COMPARE_VOROCRUST = 0, VC_COMPARE_TETGEN = 1, VC_COMPARE_SIDES = 2 };

/* One mesher's run. */
typedef struct vc_compare_side {
    const char *name;        /* "vorocrust", "tetgen" */
    char command[4096];      /* the command line that ran */
    vc_child_result run;     /* time, memory, exit */
    int ok;                  /* the mesh was made, read back and measured */
    char failure[1024];      /* why not (one line), when !ok */
    vc_mesh_report report;   /* when ok */
    /* The cut through the mesh (vc_compare.cut_axis, cut_value): the
     * segments where the plane crosses the cells' faces, in the plane's
     * two other coordinates (x1 y1 x2 y2 each). */
    double *cut;
    int64_t n_cut;
    /* From vorocrust's own summary (its log): the phase times line, and
     * whether the first sampling diverged and the surface was sampled
     * again (resample_note says how). */
    char phases[1024];
    int resampled;
    char resample_note[256];
} vc_compare_side;

typedef struct vc_compare {
    const char *input;
    int64_t input_triangles;
    double input_volume;     /* the volume the input encloses */
    double input_diagonal;   /* its bounding-box diagonal */
    int64_t tetgen_target;   /* the --target-cells given to vc-tetgen, 0 for none */
    char tetgen_bound_command[4096]; /* the run that found TetGen's volume bound */
    double bbox[6];          /* the input's bounding box */
    int cut_axis;            /* the cut's plane: coordinate cut_axis = cut_value (the */
    double cut_value;        /* axis of the box's smallest extent, through its middle) */
    char version[64];        /* vorocrust's */
    char date[64];           /* of the run, UTC */
    int threads;             /* vorocrust's threads */
    const char *work_dir;    /* the temporary directory of the meshes, NULL with --mesh-dir */
    vc_compare_side side[VC_COMPARE_SIDES];
} vc_compare;

/* The rows of the table, in order. */
int vc_compare_row_count(void);

/* Row r's name (plain ASCII, no two spaces in a row). */
const char *vc_compare_row_name(int r);

/* Row r's value for one side into buf: a number, "failed" when the side
 * failed (time and memory are shown for a run that failed), "-" when the
 * figure does not exist (no boundary, no input volume). */
void vc_compare_row_value(const vc_compare *c, int side, int r, char *buf, size_t size);

/* Writes the self-contained HTML report (the table, the commands and the
 * histograms of cell fatness and boundary triangle quality as inline SVG)
 * to path, through a temporary file renamed on success. Returns 0 or the
 * error (one line naming path). */
int vc_compare_write_html(const vc_compare *c, const char *path, vc_error *err);

#endif
