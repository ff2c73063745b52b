// Thin C++ adapter around TetGen 1.5 (Debian's libtet1.5-dev) for
// vc-tetgen: the surface goes in as a piecewise linear complex, the
// tetrahedra come out as plain C arrays. TetGen reports failures by
// throwing an int when built as a library (TETLIBRARY).
#define TETLIBRARY
#include "tetgen_adapter.h"

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <vector>

#include <tetgen.h>

// TetGen's exit codes (terminatetetgen) in words.
static const char *tetgen_failure(int code)
{
    switch (code) {
    case 1: return "out of memory";
    case 2: return "internal error";
    case 3: return "the surface intersects itself";
    case 4: return "a very small input feature size was detected";
    case 5: return "two very close input facets were detected";
    case 10: return "input error";
    default: return "unknown failure";
    }
}

extern "C" void vc_tetgen_mesh_free(vc_tetgen_mesh *m)
{
    if (!m)
        return;
    std::free(m->points);
    std::free(m->tets);
    std::memset(m, 0, sizeof *m);
}

// Copies TetGen's output into out, every tetrahedron positively oriented.
static int copy_output(const tetgenio &o, vc_tetgen_mesh *out, char *msg, size_t msg_len)
{
    const int64_t np = o.numberofpoints, nt = o.numberoftetrahedra;
    out->points = (double *)std::malloc(sizeof(double) * 3 * (size_t)(np ? np : 1));
    out->tets = (int64_t *)std::malloc(sizeof(int64_t) * 4 * (size_t)(nt ? nt : 1));
    if (!out->points || !out->tets) {
        vc_tetgen_mesh_free(out);
        std::snprintf(msg, msg_len, "out of memory for %lld tetrahedra", (long long)nt);
        return 1;
    }
    out->n_points = np;
    out->n_tets = nt;
    std::memcpy(out->points, o.pointlist, sizeof(double) * 3 * (size_t)np);
    const int first = o.firstnumber, corners = o.numberofcorners;
    for (int64_t t = 0; t < nt; t++) {
        int64_t *id = out->tets + 4 * t;
        for (int k = 0; k < 4; k++)
            id[k] = (int64_t)o.tetrahedronlist[corners * t + k] - first;
        const double *p0 = out->points + 3 * id[0], *p1 = out->points + 3 * id[1];
        const double *p2 = out->points + 3 * id[2], *p3 = out->points + 3 * id[3];
        double a[3], b[3], c[3];
        for (int d = 0; d < 3; d++) {
            a[d] = p1[d] - p0[d];
            b[d] = p2[d] - p0[d];
            c[d] = p3[d] - p0[d];
        }
        double det = (a[1] * b[2] - a[2] * b[1]) * c[0] + (a[2] * b[0] - a[0] * b[2]) * c[1] +
                     (a[0] * b[1] - a[1] * b[0]) * c[2];
        if (det < 0) {
            int64_t tmp = id[2];
            id[2] = id[3];
            id[3] = tmp;
        }
    }
    return 0;
}

// The surface as TetGen's piecewise linear complex: one facet per triangle
// (tetgenio's destructor frees every array with delete[]).
static void fill_plc(const vc_surface *s, tetgenio *in)
{
    in->firstnumber = 0;
    in->numberofpoints = (int)s->n_vertices;
    in->pointlist = new REAL[3 * (size_t)s->n_vertices];
    std::memcpy(in->pointlist, s->xyz, sizeof(double) * 3 * (size_t)s->n_vertices);
    in->numberoffacets = (int)s->n_triangles;
    in->facetlist = new tetgenio::facet[(size_t)s->n_triangles];
    for (int64_t t = 0; t < s->n_triangles; t++) {
        tetgenio::facet *f = &in->facetlist[t];
        tetgenio::init(f);
        f->numberofpolygons = 1;
        f->polygonlist = new tetgenio::polygon[1];
        tetgenio::init(f->polygonlist);
        f->polygonlist[0].numberofvertices = 3;
        f->polygonlist[0].vertexlist = new int[3];
        for (int k = 0; k < 3; k++)
            f->polygonlist[0].vertexlist[k] = (int)s->tri[3 * t + k];
    }
}

static int too_large(const vc_surface *s, char *msg, size_t msg_len)
{
    if (s->n_vertices > INT_MAX / 3 || s->n_triangles > INT_MAX) {
        std::snprintf(msg, msg_len, "too large for TetGen (%lld vertices, %lld triangles)",
                      (long long)s->n_vertices, (long long)s->n_triangles);
        return 1;
    }
    return 0;
}

extern "C" int vc_tetgen_self_intersections(const vc_surface *s, int64_t *n_triangles,
                                            char *msg, size_t msg_len)
{
    *n_triangles = 0;
    if (too_large(s, msg, msg_len))
        return 1;
    try {
        tetgenio in, o;
        fill_plc(s, &in);
        char switches[] = "dQ";
        tetgenbehavior b;
        b.parse_commandline(switches);
        tetrahedralize(&b, &in, &o);
        *n_triangles = o.numberoftrifaces;
        return 0;
    } catch (const std::bad_alloc &) {
        std::snprintf(msg, msg_len, "TetGen: out of memory");
    } catch (int code) {
        std::snprintf(msg, msg_len, "TetGen: %s (code %d)", tetgen_failure(code), code);
    } catch (...) {
        std::snprintf(msg, msg_len, "TetGen: unexpected exception");
    }
    return 1;
}

extern "C" int vc_tetgen_tetrahedralize(const vc_surface *s, const char *switches,
                                        const double *holes, int64_t n_holes, vc_tetgen_mesh *out,
                                        char *msg, size_t msg_len)
{
    std::memset(out, 0, sizeof *out);
    if (too_large(s, msg, msg_len) || n_holes > INT_MAX / 3) {
        if (n_holes > INT_MAX / 3)
            std::snprintf(msg, msg_len, "too many cavities for TetGen (%lld)", (long long)n_holes);
        return 1;
    }
    try {
        tetgenio in, o;
        fill_plc(s, &in);
        if (n_holes > 0) {
            in.numberofholes = (int)n_holes;
            in.holelist = new REAL[3 * (size_t)n_holes];
            std::memcpy(in.holelist, holes, sizeof(double) * 3 * (size_t)n_holes);
        }
        std::vector<char> sw(switches, switches + std::strlen(switches) + 1);
        tetgenbehavior b;
        if (!b.parse_commandline(sw.data())) {
            std::snprintf(msg, msg_len, "TetGen rejected the switches '%s'", switches);
            return 1;
        }
        tetrahedralize(&b, &in, &o);
        if (o.numberoftetrahedra <= 0 || o.numberofcorners < 4) {
            std::snprintf(msg, msg_len, "TetGen produced no tetrahedra");
            return 1;
        }
        return copy_output(o, out, msg, msg_len);
    } catch (const std::bad_alloc &) {
        std::snprintf(msg, msg_len, "TetGen: out of memory");
    } catch (int code) {
        std::snprintf(msg, msg_len, "TetGen: %s (code %d)", tetgen_failure(code), code);
    } catch (...) {
        std::snprintf(msg, msg_len, "TetGen: unexpected exception");
    }
    vc_tetgen_mesh_free(out);
    return 1;
}
