/* The reconstructed surface (OBJ polygons, or a .vtu of VTK_POLYGON cells)
 * and the balls (CSV), each through a temporary file. */
#include "vorocrust/io.h"
#include "io/tmpfile.h"
#include "vorocrust/sampling.h"

#include <inttypes.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcasecmp(s + n - m, suffix) == 0;
}

static void write_obj(FILE *fp, const vc_polysurface *p)
{
    fprintf(fp, "# vorocrust reconstructed surface: %" PRId64 " vertices, %" PRId64
            " polygons\n", p->n_points, p->n_polys);
    for (int64_t i = 0; i < p->n_points; i++)
        fprintf(fp, "v %.17g %.17g %.17g\n", p->points[3 * i], p->points[3 * i + 1],
                p->points[3 * i + 2]);
    for (int64_t f = 0; f < p->n_polys; f++) {
        fputc('f', fp);
        for (int64_t j = p->poly_offsets[f]; j < p->poly_offsets[f + 1]; j++)
            fprintf(fp, " %" PRId64, p->poly_vertices[j] + 1);
        fputc('\n', fp);
    }
}

static void write_vtu(FILE *fp, const vc_polysurface *p)
{
    fprintf(fp, "<?xml version=\"1.0\"?>\n"
                "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
                "header_type=\"UInt64\">\n<UnstructuredGrid>\n"
                "<Piece NumberOfPoints=\"%" PRId64 "\" NumberOfCells=\"%" PRId64 "\">\n"
                "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" "
                "format=\"ascii\">\n", p->n_points, p->n_polys);
    for (int64_t i = 0; i < p->n_points; i++)
        fprintf(fp, "%.17g %.17g %.17g\n", p->points[3 * i], p->points[3 * i + 1],
                p->points[3 * i + 2]);
    fprintf(fp, "</DataArray>\n</Points>\n<Cells>\n"
                "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for (int64_t j = 0; j < p->poly_offsets[p->n_polys]; j++)
        fprintf(fp, "%" PRId64 "\n", p->poly_vertices[j]);
    fprintf(fp, "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for (int64_t f = 0; f < p->n_polys; f++)
        fprintf(fp, "%" PRId64 "\n", p->poly_offsets[f + 1]);
    fprintf(fp, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for (int64_t f = 0; f < p->n_polys; f++)
        fputs("7\n", fp);
    fprintf(fp, "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
}

int vc_polysurface_write(const vc_polysurface *p, const char *path, vc_error *err)
{
    vc_tmpfile t;
    int rc = vc_tmpfile_open(&t, path, err);
    if (rc)
        return rc;
    if (ends_with(path, ".vtu"))
        write_vtu((FILE *)t.fp, p);
    else
        write_obj((FILE *)t.fp, p);
    return vc_tmpfile_commit(&t, err);
}

int vc_balls_write_csv(const vc_balls *b, const char *path, vc_error *err)
{
    vc_tmpfile t;
    int rc = vc_tmpfile_open(&t, path, err);
    if (rc)
        return rc;
    FILE *fp = (FILE *)t.fp;
    static const char *kinds[] = {"corner", "edge", "surface"};
    fprintf(fp, "x,y,z,radius,kind,element,nx,ny,nz\n");
    for (int64_t i = 0; i < b->n; i++)
        fprintf(fp, "%.17g,%.17g,%.17g,%.17g,%s,%" PRId64 ",%.17g,%.17g,%.17g\n",
                b->center[3 * i], b->center[3 * i + 1], b->center[3 * i + 2], b->radius[i],
                kinds[b->kind[i]], b->element[i], b->normal[3 * i], b->normal[3 * i + 1],
                b->normal[3 * i + 2]);
    return vc_tmpfile_commit(&t, err);
}
