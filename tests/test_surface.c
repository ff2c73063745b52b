/* Tests of the surface module: the reference models, every format, every
 * bad input. Environment: VC_MODELS (the shared models), VC_TMP (a
 * writable directory). */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "vorocrust/surface.h"

#include "test_check.h"
#include "test_surface_util.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static const char *tmpdir = ".";

static const char *tmp_path(const char *name)
{
    static char buf[8][1024];
    static int k = 0;
    k = (k + 1) % 8;
    snprintf(buf[k], sizeof buf[k], "%s/surface_%s", tmpdir, name);
    return buf[k];
}

static const char *write_file(const char *name, const void *data, size_t len)
{
    const char *p = tmp_path(name);
    FILE *f = fopen(p, "wb");
    if (!f) {
        fprintf(stderr, "cannot write %s\n", p);
        exit(2);
    }
    fwrite(data, 1, len, f);
    fclose(f);
    return p;
}

static const char *write_text(const char *name, const char *text)
{
    return write_file(name, text, strlen(text));
}

static int has_warning(const vc_surface_report *r, const char *needle)
{
    for (int i = 0; i < r->n_warnings; i++)
        if (strstr(r->warnings[i], needle))
            return 1;
    return 0;
}

/* Reads a file that must succeed, with the reader chosen for its
 * extension or with OpenMesh. */
static int read_ok_with(const char *path, vc_surface_reader which, vc_surface *s,
                        vc_surface_report *r)
{
    vc_error err = {0, ""};
    int rc = vc_surface_read_with(path, which, s, r, &err);
    CHECKF(rc == 0, "%s: unexpected failure: %s", path, err.msg);
    return rc == 0;
}

static int read_ok(const char *path, vc_surface *s, vc_surface_report *r)
{
    return read_ok_with(path, VC_READER_AUTO, s, r);
}

/* Reads a file that must fail with code; the message must name the file
 * and contain needle. */
static void read_fails(const char *path, int code, const char *needle)
{
    vc_surface s;
    vc_surface_report r;
    vc_error err = {0, ""};
    int rc = vc_surface_read(path, &s, &r, &err);
    CHECKF(rc == code, "%s: code %d, expected %d (%s)", path, rc, code, err.msg);
    CHECKF(strstr(err.msg, path) == err.msg, "message does not start with the file: %s", err.msg);
    CHECKF(strstr(err.msg, needle) != NULL, "message lacks '%s': %s", needle, err.msg);
    CHECKF(!strchr(err.msg, '\n'), "message is not one line: %s", err.msg);
    CHECKF(s.xyz == NULL && s.tri == NULL && s.n_triangles == 0, "%s: output not empty on failure", path);
    if (rc == 0)
        vc_surface_free(&s);
}

/* ---- The reference models. ---- */

typedef struct model_case {
    const char *file;
    int64_t euler;
    double volume, rel_tol; /* expected |volume| (0: only check > 0) */
    int polygons;           /* non-triangle faces expected */
} model_case;

static void test_models(const char *models)
{
    const model_case cases[] = {
        {"cube.off", 2, 4.0, 1e-12, 6}, /* a 2x2x2 cube turned 45 degrees about z */
        {"sphere.obj", 2, 4.0 / 3.0 * M_PI * 0.343, 0.03, 0},
        {"torus.obj", 0, 2 * M_PI * M_PI * 1.0 * 0.25, 0.04, 0},
        {"fertility.off", -6, 0, 0, 0},
        {"onebox.obj", 2, 1.0, 1e-12, 0},
        {"bracket.obj", 2, 0, 0, 0},
        {"fandisk.off", 2, 0, 0, 0},
        {"bumpy-cube.obj", 2, 0, 0, 0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const model_case *c = &cases[i];
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", models, c->file);
        vc_surface s, t;
        vc_surface_report r, q;
        if (!read_ok(path, &s, &r))
            continue;
        vc_error err = {0, ""};
        CHECKF(r.n_boundary_edges == 0 && vc_surface_require_closed(&r, &err) == 0, "%s: not closed", c->file);
        CHECKF(r.n_nonmanifold_edges == 0, "%s: %lld non-manifold edges", c->file, (long long)r.n_nonmanifold_edges);
        CHECKF(r.n_inconsistent_edges == 0, "%s: inconsistent orientation", c->file);
        CHECKF(r.n_degenerate == 0, "%s: %lld degenerate", c->file, (long long)r.n_degenerate);
        CHECKF(r.n_components == 1, "%s: %lld components", c->file, (long long)r.n_components);
        CHECKF(r.euler == c->euler, "%s: Euler %lld, expected %lld", c->file, (long long)r.euler, (long long)c->euler);
        CHECKF(r.closed_manifold && r.genus == (2 - c->euler) / 2, "%s: genus %lld", c->file, (long long)r.genus);
        CHECKF(r.volume > 0, "%s: volume %g", c->file, r.volume);
        if (c->volume > 0)
            CHECKF(fabs(r.volume - c->volume) <= c->rel_tol * c->volume, "%s: volume %.12g, expected %.12g",
                  c->file, r.volume, c->volume);
        CHECKF(r.n_polygons_triangulated == c->polygons, "%s: %lld polygons triangulated", c->file,
              (long long)r.n_polygons_triangulated);
        if (c->polygons)
            CHECKF(has_warning(&r, "6 non-triangle faces triangulated"), "%s: no triangulation warning", c->file);
        CHECKF(r.n_vertices == s.n_vertices && r.n_triangles == s.n_triangles, "%s: report counts", c->file);
        CHECKF(r.euler == r.n_vertices - r.n_edges + r.n_triangles, "%s: Euler formula", c->file);
        for (int k = 0; k < 3; k++)
            CHECKF(r.bbox[k] <= r.bbox[k + 3], "%s: bbox", c->file);

        /* Cross-check against OpenMesh's readers (float coordinates). */
        if (read_ok_with(path, VC_READER_OPENMESH, &t, &q)) {
            CHECKF(strcmp(q.reader, "OpenMesh") == 0, "%s: reader %s", c->file, q.reader);
            CHECKF(q.n_vertices == r.n_vertices && q.n_triangles == r.n_triangles && q.euler == r.euler,
                  "%s: OpenMesh reads V=%lld T=%lld chi=%lld, ours V=%lld T=%lld chi=%lld", c->file,
                  (long long)q.n_vertices, (long long)q.n_triangles, (long long)q.euler,
                  (long long)r.n_vertices, (long long)r.n_triangles, (long long)r.euler);
            CHECKF(fabs(q.volume - r.volume) <= 1e-5 * r.volume, "%s: OpenMesh volume %.9g vs %.9g", c->file,
                  q.volume, r.volume);
            vc_surface_free(&t);
        }
        vc_surface_free(&s);
    }
}

/* ---- The same box in every format. ---- */

/* Box [0, 0.2] x [0, 0.5] x [0, 0.3]: volume 0.03; vertex i = (x bit 0,
 * y bit 1, z bit 2). Quads counter-clockwise seen from outside. */
static const int box_quads[6][4] = {
    {0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
static const double box_size[3] = {0.2, 0.5, 0.3};
#define BOX_VOLUME (0.2 * 0.5 * 0.3)

static void box_vertex(int i, double p[3])
{
    for (int k = 0; k < 3; k++)
        p[k] = (i >> k & 1) ? box_size[k] : 0.0;
}

static void box_tri(int t, int v[3])
{
    const int *q = box_quads[t / 2];
    if (t % 2 == 0) {
        v[0] = q[0]; v[1] = q[1]; v[2] = q[2];
    } else {
        v[0] = q[0]; v[1] = q[2]; v[2] = q[3];
    }
}

typedef struct strbuf {
    char *s;
    size_t n, cap;
} strbuf;

static void sb_printf(strbuf *b, const char *fmt, ...)
{
    va_list ap;
    for (;;) {
        va_start(ap, fmt);
        int k = vsnprintf(b->s ? b->s + b->n : NULL, b->s ? b->cap - b->n : 0, fmt, ap);
        va_end(ap);
        if (b->s && (size_t)k < b->cap - b->n) {
            b->n += (size_t)k;
            return;
        }
        b->cap = 2 * (b->cap + (size_t)k + 64);
        b->s = realloc(b->s, b->cap);
        if (!b->s)
            exit(2);
    }
}

static void sb_bytes(strbuf *b, const void *d, size_t n)
{
    if (b->n + n + 1 > b->cap) {
        b->cap = 2 * (b->n + n + 64);
        b->s = realloc(b->s, b->cap);
        if (!b->s)
            exit(2);
    }
    memcpy(b->s + b->n, d, n);
    b->n += n;
}

static void put_le(strbuf *b, uint64_t v, int bytes)
{
    unsigned char c[8];
    for (int i = 0; i < bytes; i++)
        c[i] = (unsigned char)(v >> (8 * i));
    sb_bytes(b, c, (size_t)bytes);
}

static void put_be(strbuf *b, uint64_t v, int bytes)
{
    unsigned char c[8];
    for (int i = 0; i < bytes; i++)
        c[bytes - 1 - i] = (unsigned char)(v >> (8 * i));
    sb_bytes(b, c, (size_t)bytes);
}

static uint32_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}

static uint64_t double_bits(double d)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    return u;
}

static void check_box(const char *path, double tol, int64_t polygons, int64_t duplicates)
{
    vc_surface s;
    vc_surface_report r;
    if (!read_ok(path, &s, &r))
        return;
    CHECKF(r.n_vertices == 8 && r.n_triangles == 12, "%s: V=%lld T=%lld", path, (long long)r.n_vertices,
          (long long)r.n_triangles);
    CHECKF(r.n_boundary_edges == 0 && r.n_nonmanifold_edges == 0 && r.n_inconsistent_edges == 0,
          "%s: topology %lld/%lld/%lld", path, (long long)r.n_boundary_edges, (long long)r.n_nonmanifold_edges,
          (long long)r.n_inconsistent_edges);
    CHECKF(r.euler == 2 && r.genus == 0 && r.n_components == 1, "%s: chi=%lld", path, (long long)r.euler);
    CHECKF(r.signed_volume > 0 && fabs(r.volume - BOX_VOLUME) <= tol * BOX_VOLUME, "%s: volume %.17g", path,
          r.signed_volume);
    CHECKF(r.n_polygons_triangulated == polygons, "%s: %lld polygons", path, (long long)r.n_polygons_triangulated);
    CHECKF(r.n_duplicate_vertices == duplicates, "%s: %lld duplicates merged", path,
          (long long)r.n_duplicate_vertices);
    CHECKF(r.n_warnings == (polygons ? 1 : 0), "%s: %d warnings (%s)", path, r.n_warnings,
          r.n_warnings ? r.warnings[0] : "");
    CHECKF(fabs(r.bbox[3] - 0.2) < tol && fabs(r.bbox[4] - 0.5) < tol && fabs(r.bbox[5] - 0.3) < tol, "%s: bbox",
          path);
    vc_surface_free(&s);
}

/* The box as ASCII STL into b (emptied first): lower case and LF, or
 * upper case and CRLF; with signed_zero, every other facet writes its
 * zero coordinates as -0 (equal positions: merged all the same). */
static void ascii_stl_zeros(strbuf *b, int upper, int signed_zero);

static void ascii_stl(strbuf *b, int upper)
{
    ascii_stl_zeros(b, upper, 0);
}

static void ascii_stl_zeros(strbuf *b, int upper, int signed_zero)
{
    const char *eol = upper ? "\r\n" : "\n";
    double p[3];
    int v[3];
    b->n = 0;
    sb_printf(b, "%s%s", upper ? "SOLID BOX" : "solid box", eol);
    for (int t = 0; t < 12; t++) {
        box_tri(t, v);
        sb_printf(b, "  %s 0 0 0%s    %s%s", upper ? "FACET NORMAL" : "facet normal", eol,
                  upper ? "OUTER LOOP" : "outer loop", eol);
        for (int k = 0; k < 3; k++) {
            box_vertex(v[k], p);
            for (int d = 0; d < 3 && signed_zero && t % 2; d++)
                if (p[d] == 0)
                    p[d] = -0.0;
            sb_printf(b, "      %s %.9g %.9g %.9g%s", upper ? "VERTEX" : "vertex", p[0], p[1], p[2], eol);
        }
        sb_printf(b, "    %s%s  %s%s", upper ? "ENDLOOP" : "endloop", eol, upper ? "EndFacet" : "endfacet",
                  eol);
    }
    sb_printf(b, "%s%s", upper ? "ENDSOLID BOX" : "endsolid box", eol);
}

static void test_formats(void)
{
    double p[3];
    int v[3];
    strbuf b = {0};

    /* OBJ: triangles, negative (relative) indices in one face, v/t/n forms. */
    sb_printf(&b, "# box\no box\n");
    for (int i = 0; i < 8; i++) {
        box_vertex(i, p);
        sb_printf(&b, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
    }
    sb_printf(&b, "vn 0 0 1\n");
    for (int t = 0; t < 12; t++) {
        box_tri(t, v);
        if (t == 0)
            sb_printf(&b, "f %d %d %d\n", v[0] - 8, v[1] - 8, v[2] - 8);
        else if (t == 1)
            sb_printf(&b, "f %d//1 %d//1 %d//1\n", v[0] + 1, v[1] + 1, v[2] + 1);
        else
            sb_printf(&b, "f %d/%d %d/%d %d/%d\n", v[0] + 1, 1, v[1] + 1, 1, v[2] + 1, 1);
    }
    check_box(write_file("box.obj", b.s, b.n), 1e-14, 0, 0);

    /* OFF: quads. */
    b.n = 0;
    sb_printf(&b, "OFF\n# comment\n8 6 0\n");
    for (int i = 0; i < 8; i++) {
        box_vertex(i, p);
        sb_printf(&b, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
    }
    for (int f = 0; f < 6; f++)
        sb_printf(&b, "4 %d %d %d %d\n", box_quads[f][0], box_quads[f][1], box_quads[f][2], box_quads[f][3]);
    check_box(write_file("box.off", b.s, b.n), 1e-14, 6, 0);

    /* ASCII STL, and in upper case with CRLF, as some writers do (VTK
     * reads it). */
    ascii_stl(&b, 0);
    check_box(write_file("box_ascii.stl", b.s, b.n), 1e-14, 0, 28);
    ascii_stl(&b, 1);
    check_box(write_file("box_upper_ascii.stl", b.s, b.n), 1e-14, 0, 28);
    ascii_stl_zeros(&b, 0, 1);
    check_box(write_file("box_signed_zeros.stl", b.s, b.n), 1e-14, 0, 28);

    /* OBJ with long face lines continued by a backslash (LF and CRLF), a
     * vertex line too. */
    b.n = 0;
    for (int i = 0; i < 8; i++) {
        box_vertex(i, p);
        sb_printf(&b, i == 3 ? "v %.17g \\\n %.17g %.17g\n" : "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
    }
    for (int t = 0; t < 12; t++) {
        box_tri(t, v);
        sb_printf(&b, t % 2 ? "f %d %d \\\n   %d\n" : "f %d \\\r\n%d %d\r\n", v[0] + 1, v[1] + 1, v[2] + 1);
    }
    check_box(write_file("box_continued.obj", b.s, b.n), 1e-14, 0, 0);

    /* Binary STL (float: tolerance of float rounding). The header starts
     * with "solid" as some exporters do. */
    b.n = 0;
    char header[80] = "solid written by test_surface";
    sb_bytes(&b, header, 80);
    put_le(&b, 12, 4);
    for (int t = 0; t < 12; t++) {
        box_tri(t, v);
        for (int k = 0; k < 3; k++)
            put_le(&b, float_bits(0.0f), 4);
        for (int k = 0; k < 3; k++) {
            box_vertex(v[k], p);
            for (int d = 0; d < 3; d++)
                put_le(&b, float_bits((float)p[d]), 4);
        }
        put_le(&b, 0, 2);
    }
    check_box(write_file("box_binary.stl", b.s, b.n), 1e-6, 0, 28);

    /* PLY ASCII with quads and an extra property and element. */
    b.n = 0;
    sb_printf(&b, "ply\nformat ascii 1.0\ncomment box\nelement vertex 8\nproperty float x\nproperty float y\n"
                  "property float z\nproperty uchar red\nelement face 6\nproperty list uchar int vertex_indices\n"
                  "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n");
    for (int i = 0; i < 8; i++) {
        box_vertex(i, p);
        sb_printf(&b, "%.17g %.17g %.17g 255\n", p[0], p[1], p[2]);
    }
    for (int f = 0; f < 6; f++)
        sb_printf(&b, "4 %d %d %d %d\n", box_quads[f][0], box_quads[f][1], box_quads[f][2], box_quads[f][3]);
    sb_printf(&b, "0 1\n");
    check_box(write_file("box_ascii.ply", b.s, b.n), 1e-14, 6, 0);

    /* PLY binary little and big endian, double coordinates, triangles,
     * with a normal property to skip. */
    for (int big = 0; big < 2; big++) {
        b.n = 0;
        sb_printf(&b, "ply\nformat %s 1.0\nelement vertex 8\nproperty double x\nproperty double y\n"
                      "property double z\nproperty float nx\nelement face 12\n"
                      "property list uchar uint vertex_indices\nend_header\n",
                  big ? "binary_big_endian" : "binary_little_endian");
        void (*put)(strbuf *, uint64_t, int) = big ? put_be : put_le;
        for (int i = 0; i < 8; i++) {
            box_vertex(i, p);
            for (int d = 0; d < 3; d++)
                put(&b, double_bits(p[d]), 8);
            put(&b, float_bits(1.0f), 4);
        }
        for (int t = 0; t < 12; t++) {
            box_tri(t, v);
            put(&b, 3, 1);
            for (int k = 0; k < 3; k++)
                put(&b, (uint64_t)v[k], 4);
        }
        check_box(write_file(big ? "box_be.ply" : "box_le.ply", b.s, b.n), 1e-14, 0, 0);
    }

    /* Upper-case extension. */
    b.n = 0;
    sb_printf(&b, "OFF 8 12 0\n");
    for (int i = 0; i < 8; i++) {
        box_vertex(i, p);
        sb_printf(&b, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
    }
    for (int t = 0; t < 12; t++) {
        box_tri(t, v);
        sb_printf(&b, "3 %d %d %d 0.5 0.5 0.5\n", v[0], v[1], v[2]); /* with a face colour */
    }
    check_box(write_file("box_upper.OFF", b.s, b.n), 1e-14, 0, 0);
    free(b.s);
}

/* ---- Bad inputs. ---- */

/* OBJ text of the box (0-based triangle list), with triangle `flip`
 * reversed, triangles `skip_from`..`skip_to` left out and `extra` appended. */
static const char *box_obj(const char *name, int flip, int skip_from, int skip_to, const char *extra)
{
    strbuf b = {0};
    double p[3];
    int v[3];
    for (int i = 0; i < 8; i++) {
        box_vertex(i, p);
        sb_printf(&b, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
    }
    for (int t = 0; t < 12; t++) {
        if (t >= skip_from && t <= skip_to)
            continue;
        box_tri(t, v);
        if (t == flip)
            sb_printf(&b, "f %d %d %d\n", v[0] + 1, v[2] + 1, v[1] + 1);
        else
            sb_printf(&b, "f %d %d %d\n", v[0] + 1, v[1] + 1, v[2] + 1);
    }
    sb_printf(&b, "%s", extra ? extra : "");
    const char *path = write_file(name, b.s, b.n);
    free(b.s);
    return path;
}

static void test_bad_inputs(void)
{
    vc_surface s;
    vc_surface_report r;
    vc_error err = {0, ""};

    read_fails(tmp_path("does_not_exist.obj"), VC_EIO, "cannot open");
    read_fails(write_text("points.xyz", "0 0 0\n"), VC_EFORMAT, "unsupported file extension '.xyz'");
    read_fails(write_text("noext", "0 0 0\n"), VC_EFORMAT, "unsupported file extension");
    read_fails(write_text("empty.obj", ""), VC_EFORMAT, "empty file");
    read_fails(write_text("blank.stl", "  \n\n"), VC_EFORMAT, "empty file");
    read_fails(write_text("novertices.obj", "# nothing\n"), VC_EINPUT, "no triangles");
    read_fails(write_text("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n"), VC_EINPUT,
               "vertex 3 has a non-finite coordinate");
    read_fails(write_text("inf.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 inf 0\n3 0 1 2\n"), VC_EINPUT,
               "non-finite");
    read_fails(write_text("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"), VC_EINPUT,
               "face 1 refers to vertex 4, but the file has 3 vertices");
    read_fails(write_text("malformed.obj", "v 0 0 0\nv 1 zero 0\n"), VC_EFORMAT, "line 2: malformed vertex");
    read_fails(write_text("twoverts.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n"), VC_EFORMAT, "line 3: face with 2 vertices");
    read_fails(write_text("short.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n"), VC_EFORMAT,
               "file ends after 1 of 2 faces");
    read_fails(write_text("noheader.off", "4 2 0\n"), VC_EFORMAT, "missing OFF header");
    read_fails(write_text("bad.stl", "this is not an STL file\n"), VC_EFORMAT, "malformed STL");
    read_fails(write_text("bad.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n"),
               VC_EFORMAT, "without x, y and z");
    read_fails(write_text("truncated.ply",
                          "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                          "property float y\nproperty float z\nend_header\n\x01\x02"),
               VC_EFORMAT, "file ends inside element 'vertex'");
    read_fails(write_text("alldegenerate.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"), VC_EINPUT,
               "all 1 triangles are degenerate");
    read_fails(write_text("allcollapsed.obj", "v 0 0 0\nv 1 0 0\nf 1 1 2\n"), VC_EINPUT,
               "every triangle repeats a vertex");

    /* Strict parsing, the real value in the message (issue 17). */
    {
        static const char tet_v[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
        static const char tet_off[] = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
        char t[512];
        snprintf(t, sizeof t, "%sf 2.7 3 4\n", tet_v);
        read_fails(write_text("frac.obj", t), VC_EFORMAT, "line 5: malformed face index");
        snprintf(t, sizeof t, "%sf 1 2 3x\n", tet_v);
        read_fails(write_text("junk.obj", t), VC_EFORMAT, "line 5: malformed face index");
        snprintf(t, sizeof t, "%sf -5 1 2\n", tet_v);
        read_fails(write_text("rel.obj", t), VC_EINPUT, "relative face index -5 refers before the first vertex");
        snprintf(t, sizeof t, "%sf 1/1/1 2//2 9223372036854775807\n", tet_v);
        read_fails(write_text("huge.obj", t), VC_EINPUT, "refers to vertex 9223372036854775807");
        snprintf(t, sizeof t, "OFF\n4 4 0\n%s3 0 1 9223372036854775807\n", tet_off);
        read_fails(write_text("int64max.off", t), VC_EFORMAT, "data after the 4 faces");
        snprintf(t, sizeof t, "OFF\n4 3 0\n%s", tet_off);
        read_fails(write_text("surplus.off", t), VC_EFORMAT, "line 10: data after the 3 faces");
        read_fails(write_text("idx.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 9223372036854775807\n"),
                   VC_EINPUT, "refers to vertex 9223372036854775807, but the file has 4 vertices (numbered from 0)");
        read_fails(write_text("4d.off", "4OFF\n0 0 0\n"), VC_EFORMAT, "4OFF (vertex dimension other than 3)");
        read_fails(write_text("word.off", "OFFx\n0 0 0\n"), VC_EFORMAT, "missing OFF header (found 'OFFx')");
        snprintf(t, sizeof t,
                 "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face 3\nproperty list uchar int vertex_indices\nend_header\n%s", tet_off);
        read_fails(write_text("surplus.ply", t), VC_EFORMAT, "data after the last element");
        snprintf(t, sizeof t,
                 "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face 1\nproperty list uchar int vertex_indices\nend_header\n%snan 0 1 2\n", "0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
        read_fails(write_text("nan.ply", t), VC_EFORMAT, "list length nan is not an integer");
        read_fails(write_text("ctrl.ply", "ply\nformat \x1b[1m 1.0\n"), VC_EFORMAT, "unknown PLY format '\\x1b[1m'");
        /* Binary STL whose header starts with "solid" and whose count is wrong. */
        unsigned char stl[184];
        memset(stl, 0, sizeof stl);
        memcpy(stl, "solid x", 7);
        stl[80] = 5;
        read_fails(write_file("solid.stl", stl, sizeof stl), VC_EFORMAT,
                   "binary STL: the header announces 5 triangles (334 bytes) but the file has 184 bytes");
        /* Binary OFF with counts beyond the file. */
        unsigned char boff[11 + 12 + 8] = "OFF BINARY\n";
        boff[11] = 0xff;
        boff[12] = 0xff;
        boff[13] = 0xff;
        read_fails(write_file("huge_binary.off", boff, sizeof boff), VC_EFORMAT,
                   "binary OFF: the header announces 16777215 vertices");
        mkdir(tmp_path("dir.obj"), 0755);
        read_fails(tmp_path("dir.obj"), VC_EIO, "dir.obj: is a directory");
    }

    /* Degenerate triangle (kept, counted) and a triangle repeating a
     * vertex (removed, counted), next to the closed box. */
    const char *path = box_obj("degenerate.obj", -1, 99, 99,
                               "v 5 0 0\nv 6 0 0\nv 7 0 0\nf 9 10 11\nf 1 1 2\nv 9 9 9\n");
    if (read_ok(path, &s, &r)) {
        CHECKF(r.n_degenerate == 1, "degenerate %lld", (long long)r.n_degenerate);
        CHECKF(r.n_collapsed == 1, "collapsed %lld", (long long)r.n_collapsed);
        CHECKF(r.n_unused_vertices == 1, "unused %lld", (long long)r.n_unused_vertices);
        CHECKF(r.n_triangles == 13 && r.n_vertices == 11, "T=%lld V=%lld", (long long)r.n_triangles,
              (long long)r.n_vertices);
        CHECKF(r.n_components == 2, "components %lld", (long long)r.n_components);
        CHECKF(has_warning(&r, "1 degenerate (zero-area) triangles"), "no degenerate warning");
        CHECKF(has_warning(&r, "1 triangles repeat a vertex"), "no collapsed warning");
        CHECKF(has_warning(&r, "1 vertices used by no face"), "no unused warning");
        CHECKF(r.n_boundary_edges == 3, "boundary %lld", (long long)r.n_boundary_edges);
        vc_surface_free(&s);
    }

    /* Open surface: the box without its top (triangles 2, 3). */
    path = box_obj("open.obj", -1, 2, 3, NULL);
    if (read_ok(path, &s, &r)) {
        CHECKF(r.n_boundary_edges == 4, "boundary %lld", (long long)r.n_boundary_edges);
        CHECKF(!r.closed_manifold && r.genus == -1, "open surface reported closed");
        CHECKF(r.euler == 1, "chi %lld", (long long)r.euler);
        CHECKF(has_warning(&r, "4 open boundary edges (surface is not closed)"), "no boundary warning");
        int rc = vc_surface_require_closed(&r, &err);
        CHECKF(rc == VC_EINPUT, "require_closed returned %d", rc);
        CHECKF(strstr(err.msg, path) == err.msg && strstr(err.msg, "4 open boundary edges"), "message: %s", err.msg);
        vc_surface_free(&s);
    }

    /* Inconsistent orientation: one triangle flipped -> its 3 edges. */
    path = box_obj("flipped.obj", 5, 99, 99, NULL);
    if (read_ok(path, &s, &r)) {
        CHECKF(r.n_inconsistent_edges == 3, "inconsistent %lld", (long long)r.n_inconsistent_edges);
        CHECKF(r.n_boundary_edges == 0 && r.n_triangles == 12, "flipped triangle lost");
        CHECKF(has_warning(&r, "3 inconsistently oriented edges"), "no orientation warning");
        vc_surface_free(&s);
    }

    /* Inward orientation: every triangle flipped (OFF with reversed quads). */
    {
        strbuf b = {0};
        double p[3];
        sb_printf(&b, "OFF\n8 6 0\n");
        for (int i = 0; i < 8; i++) {
            box_vertex(i, p);
            sb_printf(&b, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
        }
        for (int f = 0; f < 6; f++)
            sb_printf(&b, "4 %d %d %d %d\n", box_quads[f][3], box_quads[f][2], box_quads[f][1], box_quads[f][0]);
        path = write_file("inward.off", b.s, b.n);
        free(b.s);
        if (read_ok(path, &s, &r)) {
            CHECKF(r.signed_volume < 0 && fabs(r.volume - BOX_VOLUME) < 1e-14, "inward volume %g", r.signed_volume);
            CHECKF(has_warning(&r, "oriented inward"), "no inward warning");
            CHECKF(r.n_inconsistent_edges == 0, "inward box inconsistent");
            vc_surface_free(&s);
        }
    }

    /* Non-manifold edge kept: two outward tetrahedra sharing the edge 0-1
     * (4 triangles on it). */
    {
        const double tv[6][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, -1, 0}, {0, 0, -1}};
        const int tets[2][4] = {{0, 1, 2, 3}, {0, 1, 4, 5}};
        strbuf b = {0};
        for (int i = 0; i < 6; i++)
            sb_printf(&b, "v %g %g %g\n", tv[i][0], tv[i][1], tv[i][2]);
        for (int k = 0; k < 2; k++) {
            double c[3] = {0, 0, 0};
            for (int j = 0; j < 4; j++)
                for (int d = 0; d < 3; d++)
                    c[d] += 0.25 * tv[tets[k][j]][d];
            for (int j = 0; j < 4; j++) {
                int a = tets[k][j], bb = tets[k][(j + 1) % 4], cc = tets[k][(j + 2) % 4];
                const double *A = tv[a], *B = tv[bb], *C = tv[cc];
                double u[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]}, w[3] = {C[0] - A[0], C[1] - A[1], C[2] - A[2]};
                double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
                double dot = n[0] * (A[0] - c[0]) + n[1] * (A[1] - c[1]) + n[2] * (A[2] - c[2]);
                if (dot > 0)
                    sb_printf(&b, "f %d %d %d\n", a + 1, bb + 1, cc + 1);
                else
                    sb_printf(&b, "f %d %d %d\n", a + 1, cc + 1, bb + 1);
            }
        }
        path = write_file("nonmanifold.obj", b.s, b.n);
        free(b.s);
        if (read_ok(path, &s, &r)) {
            CHECKF(r.n_triangles == 8, "non-manifold faces dropped: %lld triangles", (long long)r.n_triangles);
            CHECKF(r.n_nonmanifold_edges == 1, "non-manifold %lld", (long long)r.n_nonmanifold_edges);
            CHECKF(r.n_boundary_edges == 0 && r.n_inconsistent_edges == 0, "boundary %lld inconsistent %lld",
                  (long long)r.n_boundary_edges, (long long)r.n_inconsistent_edges);
            CHECKF(!r.closed_manifold && r.genus == -1, "non-manifold reported manifold");
            CHECKF(fabs(r.volume - 2.0 / 6.0) < 1e-14, "volume %g", r.volume);
            CHECKF(has_warning(&r, "1 non-manifold edges"), "no non-manifold warning");
            CHECKF(vc_surface_require_closed(&r, &err) == 0, "closed non-manifold refused");
            vc_surface_free(&s);
        }
        /* The same through OpenMesh: the recording importer keeps them. */
        if (read_ok_with(path, VC_READER_OPENMESH, &s, &r)) {
            CHECKF(r.n_triangles == 8 && r.n_nonmanifold_edges == 1, "OpenMesh path: T=%lld nm=%lld",
                  (long long)r.n_triangles, (long long)r.n_nonmanifold_edges);
            vc_surface_free(&s);
        }
    }

    /* vc_surface_check on an in-memory surface and a bad index. */
    {
        double xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        int64_t tri[3] = {0, 1, 3};
        vc_surface m = {3, xyz, 1, tri, NULL, 0, NULL};
        vc_surface_report rr;
        memset(&rr, 0, sizeof rr);
        CHECKF(vc_surface_check(&m, &rr, &err) == VC_EINPUT && strstr(err.msg, "refers to vertex 4"),
              "bad index: %s", err.msg);
        tri[2] = 2;
        memset(&rr, 0, sizeof rr);
        CHECKF(vc_surface_check(&m, &rr, &err) == 0 && rr.n_boundary_edges == 3 && rr.euler == 1,
              "single triangle: boundary %lld", (long long)rr.n_boundary_edges);
    }
    vc_surface_free(NULL);
}

/* vc_surface_canonical_order: a sphere with two groups, renumbered and its
 * triangles shuffled and rotated, comes out as the same arrays as the
 * original; orientation, groups and the map back to the input hold. */
static void test_canonical_order(void)
{
    builder b = {0};
    make_sphere(&b, 12, 7);
    const int64_t nv = b.s.n_vertices, nt = b.s.n_triangles;
    b.s.n_groups = 2;
    b.s.group_name = calloc(2, sizeof *b.s.group_name);
    b.s.tri_group = malloc(sizeof(int32_t) * (size_t)nt);
    snprintf(b.s.group_name[0], 64, "north");
    snprintf(b.s.group_name[1], 64, "south");
    for (int64_t t = 0; t < nt; t++) {
        double z = 0;
        for (int k = 0; k < 3; k++)
            z += b.s.xyz[3 * b.s.tri[3 * t + k] + 2];
        b.s.tri_group[t] = z < 0;
    }
    /* the same surface, renumbered: vertex v becomes perm[v], triangle t
     * goes to place order[t], starting at its corner t % 3 */
    vc_surface p = b.s;
    int64_t *perm = malloc(sizeof(int64_t) * (size_t)nv), *order = malloc(sizeof(int64_t) * (size_t)nt);
    p.xyz = malloc(sizeof(double) * 3 * (size_t)nv);
    p.tri = malloc(sizeof(int64_t) * 3 * (size_t)nt);
    p.tri_group = malloc(sizeof(int32_t) * (size_t)nt);
    CHECK(nv == 74 && nt == 144); /* 5 is prime to both: the maps are permutations */
    for (int64_t v = 0; v < nv; v++)
        perm[v] = (v * 5 + 11) % nv;
    for (int64_t t = 0; t < nt; t++)
        order[t] = (t * 5 + 3) % nt;
    for (int64_t v = 0; v < nv; v++)
        memcpy(p.xyz + 3 * perm[v], b.s.xyz + 3 * v, sizeof(double) * 3);
    for (int64_t t = 0; t < nt; t++) {
        for (int k = 0; k < 3; k++)
            p.tri[3 * order[t] + k] = perm[b.s.tri[3 * t + (k + t) % 3]];
        p.tri_group[order[t]] = b.s.tri_group[t];
    }
    vc_surface c0, c1;
    int64_t *from0 = malloc(sizeof(int64_t) * (size_t)nt), *from1 = malloc(sizeof(int64_t) * (size_t)nt);
    vc_error err = {0};
    CHECK(vc_surface_canonical_order(&b.s, &c0, from0, NULL, &err) == 0);
    int64_t *vfrom1 = malloc(sizeof(int64_t) * (size_t)nv);
    CHECK(vc_surface_canonical_order(&p, &c1, from1, vfrom1, &err) == 0);
    for (int64_t v = 0; v < nv; v++)
        CHECK(!memcmp(c1.xyz + 3 * v, p.xyz + 3 * vfrom1[v], sizeof(double) * 3));
    free(vfrom1);
    CHECK(c0.n_vertices == nv && c1.n_vertices == nv && c0.n_triangles == nt && c1.n_triangles == nt);
    CHECK(!memcmp(c0.xyz, c1.xyz, sizeof(double) * 3 * (size_t)nv));
    CHECK(!memcmp(c0.tri, c1.tri, sizeof(int64_t) * 3 * (size_t)nt));
    CHECK(!memcmp(c0.tri_group, c1.tri_group, sizeof(int32_t) * (size_t)nt));
    CHECK(c0.n_groups == 2 && !strcmp(c0.group_name[1], "south"));
    CHECK(fabs(vc_surface_signed_volume(&c0) - vc_surface_signed_volume(&b.s)) <=
          1e-12 * vc_surface_signed_volume(&b.s));
    int64_t bad = 0;
    for (int64_t t = 0; t < nt; t++) {
        /* the same corners in the same cyclic order as the input's */
        const int64_t *a = c1.tri + 3 * t, *q = p.tri + 3 * from1[t];
        int same = 0;
        for (int r = 0; r < 3; r++) {
            int all = 1;
            for (int k = 0; k < 3; k++)
                all &= !memcmp(c1.xyz + 3 * a[k], p.xyz + 3 * q[(k + r) % 3], sizeof(double) * 3);
            same |= all;
        }
        bad += !same || c1.tri_group[t] != p.tri_group[from1[t]];
        /* neighbours in memory: every triangle starts at its smallest vertex */
        bad += !(a[0] < a[1] && a[0] < a[2]);
    }
    CHECKF(bad == 0, "%lld triangles not the input's", (long long)bad);
    vc_surface_free(&c0);
    vc_surface_free(&c1);
    p.group_name = NULL; /* b's */
    vc_surface_free(&p);
    vc_surface_free(&b.s);
    free(perm);
    free(order);
    free(from0);
    free(from1);
}

int main(void)
{
    const char *models = getenv("VC_MODELS");
    const char *t = getenv("VC_TMP");
    if (t && *t)
        tmpdir = t;
    if (models && *models)
        test_models(models);
    else
        fprintf(stderr, "VC_MODELS not set: reference models skipped\n");
    test_formats();
    test_bad_inputs();
    test_canonical_order();
    if (failures) {
        fprintf(stderr, "test_surface: %d failures\n", failures);
        return 1;
    }
    printf("test_surface: all passed\n");
    return 0;
}
