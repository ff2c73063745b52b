/* VTK XML UnstructuredGrid writer for polyhedral meshes.
 *
 * File layout (VTK file version 1.0, what VTK 9.1 / ParaView 5.11 read):
 *   - every cell is a VTK_POLYHEDRON (42);
 *   - Cells/connectivity lists each cell's distinct point ids (in order of
 *     first appearance in its faces), Cells/offsets the end of each cell's
 *     run in connectivity;
 *   - Cells/faces holds, per cell, [nfaces, n0, ids0..., n1, ids1...] with
 *     global point ids and every face oriented outward for that cell;
 *     Cells/faceoffsets the end of each cell's record in faces;
 *   - all arrays are binary appended data with UInt64 headers, either raw
 *     (byte count, then the bytes) or zlib-compressed in blocks (nblocks,
 *     block size, size of the partial last block or 0, the compressed size
 *     of every block, then the compressed blocks).
 *
 * Every array's size is known before it is written, so the data is streamed
 * through a fixed buffer; zlib blocks are compressed in parallel in batches.
 * The offset attributes of the XML header are patched at the end (their
 * room is reserved with trailing blanks outside the quotes). */
#include "vorocrust/io.h"
#include "io/tmpfile.h"
#include "io/vtu_byte_order.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <libdeflate.h>
#ifdef _OPENMP
#include <omp.h>
#endif

/* The zlib-format blocks are made by libdeflate at level 1: 2.7 times
 * faster than zlib's compress2 at its fastest on a mesh's arrays (bunny.off:
 * 39 MB in 0.30 s against 0.83 s, 45% of the size against 44%), which had
 * been most of writing a mesh. Blocks of 512 KiB, 16 compressed at a time
 * (VTK's own blocks are 32 KiB; its reader takes any size). */
#define VTU_BLOCK ((size_t)524288)
#define VTU_BATCH ((size_t)16)        /* zlib blocks compressed per batch */
#define VTU_RAW_BUF ((size_t)1 << 20) /* raw streaming buffer */
#define VTU_ZLEVEL 1                  /* libdeflate's fastest */
#define VTU_OFFSET_ROOM 22            /* room for "<20 digits>" */
#define VTK_POLYHEDRON_TYPE 42


/* ---- appended-data stream ------------------------------------------- */

typedef struct vtu_stream {
    FILE *fp;
    vc_vtu_encoding enc;
    int err_no;            /* first write error (errno), 0 if none */
    int zerr;              /* zlib failure */
    long data_start;       /* file position just after the '_' marker */

    unsigned char *buf;    /* uncompressed bytes waiting to be written */
    size_t cap, len;

    /* current array */
    uint64_t total;        /* announced size in bytes */
    uint64_t fed;          /* bytes given so far */

    /* zlib */
    unsigned char *cbuf;   /* VTU_BATCH compressed blocks */
    size_t cbound;         /* room per compressed block */
    size_t *clen;          /* VTU_BATCH compressed sizes */
    struct libdeflate_compressor **zc; /* one per thread of the batches */
    int n_zc;
    uint64_t *zheader;     /* 3 + nblocks words for the current array */
    size_t zheader_cap;
    uint64_t nblocks, iblock;
    long zheader_pos;
} vtu_stream;

static void vtu_fwrite(vtu_stream *s, const void *p, size_t n)
{
    if (s->err_no || n == 0)
        return;
    if (fwrite(p, 1, n, s->fp) != n)
        s->err_no = errno ? errno : EIO;
}

/* Compresses and writes the blocks held in s->buf (all full except
 * possibly the last block of the array). */
static void vtu_flush_zlib(vtu_stream *s)
{
    size_t len = s->len;
    int nb = (int)((len + VTU_BLOCK - 1) / VTU_BLOCK);
    int zfail = 0;
    if (s->zerr || s->iblock + (uint64_t)nb > s->nblocks) {
        s->zerr = 1; /* allocation failure, or more data than announced */
        s->len = 0;
        return;
    }
#pragma omp parallel for schedule(static) num_threads(s->n_zc) if (nb > 1) reduction(| : zfail)
    for (int b = 0; b < nb; ++b) {
        size_t off = (size_t)b * VTU_BLOCK;
        size_t n = len - off < VTU_BLOCK ? len - off : VTU_BLOCK;
#ifdef _OPENMP
        struct libdeflate_compressor *zc = s->zc[omp_get_thread_num()];
#else
        struct libdeflate_compressor *zc = s->zc[0];
#endif
        /* 0: the block did not fit in cbound, which the bound rules out */
        s->clen[b] = libdeflate_zlib_compress(zc, s->buf + off, n,
                                              s->cbuf + (size_t)b * s->cbound, s->cbound);
        zfail |= s->clen[b] == 0;
    }
    if (zfail) {
        s->zerr = 1;
        return;
    }
    for (int b = 0; b < nb; ++b) {
        vtu_fwrite(s, s->cbuf + (size_t)b * s->cbound, (size_t)s->clen[b]);
        s->zheader[3 + s->iblock++] = (uint64_t)s->clen[b];
    }
    s->len = 0;
}

static void vtu_flush(vtu_stream *s)
{
    if (s->len == 0)
        return;
    if (s->enc == VC_VTU_ZLIB) {
        vtu_flush_zlib(s);
    } else {
        vtu_fwrite(s, s->buf, s->len);
        s->len = 0;
    }
}

static int vtu_stream_init(vtu_stream *s, FILE *fp, vc_vtu_encoding enc)
{
    memset(s, 0, sizeof *s);
    s->fp = fp;
    s->enc = enc;
    if (enc == VC_VTU_ZLIB) {
        s->cap = VTU_BLOCK * VTU_BATCH;
#ifdef _OPENMP
        s->n_zc = omp_get_max_threads();
#else
        s->n_zc = 1;
#endif
        s->zc = calloc((size_t)s->n_zc, sizeof *s->zc);
        if (!s->zc)
            return VC_ENOMEM;
        for (int t = 0; t < s->n_zc; t++)
            if (!(s->zc[t] = libdeflate_alloc_compressor(VTU_ZLEVEL)))
                return VC_ENOMEM;
        s->cbound = libdeflate_zlib_compress_bound(s->zc[0], VTU_BLOCK);
        s->cbuf = malloc(s->cbound * VTU_BATCH);
        s->clen = malloc(sizeof *s->clen * VTU_BATCH);
        if (!s->cbuf || !s->clen)
            return VC_ENOMEM;
    } else {
        s->cap = VTU_RAW_BUF;
    }
    s->buf = malloc(s->cap);
    return s->buf ? VC_OK : VC_ENOMEM;
}

static void vtu_stream_free(vtu_stream *s)
{
    free(s->buf);
    free(s->cbuf);
    free(s->clen);
    free(s->zheader);
    for (int t = 0; t < s->n_zc; t++)
        if (s->zc[t])
            libdeflate_free_compressor(s->zc[t]);
    free(s->zc);
}

/* Starts an array of nbytes bytes; returns its offset in the appended data. */
static uint64_t vtu_begin(vtu_stream *s, uint64_t nbytes)
{
    long pos = ftell(s->fp);
    if (pos < 0 && !s->err_no)
        s->err_no = errno ? errno : EIO;
    uint64_t offset = (uint64_t)(pos - s->data_start);
    s->total = nbytes;
    s->fed = 0;
    s->len = 0;
    if (s->enc == VC_VTU_ZLIB) {
        s->nblocks = (nbytes + VTU_BLOCK - 1) / VTU_BLOCK;
        size_t words = 3 + (size_t)s->nblocks;
        if (words > s->zheader_cap) {
            free(s->zheader);
            s->zheader = malloc(words * sizeof *s->zheader);
            s->zheader_cap = s->zheader ? words : 0;
            if (!s->zheader) {
                s->zerr = 1;
                return offset;
            }
        }
        memset(s->zheader, 0, words * sizeof *s->zheader);
        s->zheader[0] = s->nblocks;
        s->zheader[1] = VTU_BLOCK;
        s->zheader[2] = nbytes % VTU_BLOCK;
        s->iblock = 0;
        s->zheader_pos = pos;
        /* placeholder, patched by vtu_end */
        vtu_fwrite(s, s->zheader, words * sizeof *s->zheader);
    } else {
        uint64_t h = nbytes;
        vtu_fwrite(s, &h, sizeof h);
    }
    return offset;
}

static void vtu_put(vtu_stream *s, const void *p, size_t n)
{
    const unsigned char *c = p;
    s->fed += n;
    if (s->enc == VC_VTU_RAW && s->len == 0 && n >= s->cap) {
        vtu_fwrite(s, c, n); /* large array: no copy */
        return;
    }
    while (n > 0) {
        size_t room = s->cap - s->len;
        size_t k = n < room ? n : room;
        memcpy(s->buf + s->len, c, k);
        s->len += k;
        c += k;
        n -= k;
        if (s->len == s->cap)
            vtu_flush(s);
    }
}

/* One value of n bytes (4 or 8): copied straight into the buffer when it
 * fits (the common case: a call per index of a large mesh). */
static inline void vtu_put_small(vtu_stream *s, const void *p, size_t n)
{
    if (s->cap - s->len >= n) {
        memcpy(s->buf + s->len, p, n);
        s->len += n;
        s->fed += n;
        if (s->len == s->cap)
            vtu_flush(s);
    } else {
        vtu_put(s, p, n);
    }
}

static inline void vtu_put_i64(vtu_stream *s, int64_t v) { vtu_put_small(s, &v, sizeof v); }

/* An index (point id, count or offset) as Int32 (w 4) or Int64 (w 8). */
static inline void vtu_put_index(vtu_stream *s, int64_t v, int w)
{
    if (w == 8) {
        vtu_put_i64(s, v);
        return;
    }
    const int32_t x = (int32_t)v;
    vtu_put_small(s, &x, sizeof x);
}

/* Ends the current array; returns 0 if all went well. */
static int vtu_end(vtu_stream *s)
{
    vtu_flush(s);
    if (s->fed != s->total)
        return VC_EINTERNAL;
    if (s->enc == VC_VTU_ZLIB && !s->zerr && !s->err_no) {
        if (s->iblock != s->nblocks)
            return VC_EINTERNAL;
        long end = ftell(s->fp);
        if (end < 0 || fseek(s->fp, s->zheader_pos, SEEK_SET) != 0) {
            s->err_no = errno ? errno : EIO;
        } else {
            vtu_fwrite(s, s->zheader, (3 + (size_t)s->nblocks) * sizeof *s->zheader);
            if (!s->err_no && fseek(s->fp, end, SEEK_SET) != 0)
                s->err_no = errno ? errno : EIO;
        }
    }
    if (s->zerr)
        return VC_ENOMEM;
    return s->err_no ? VC_EIO : VC_OK;
}

/* ---- XML header ------------------------------------------------------ */

enum {
    A_REGION, A_SEED, A_VOLUME, A_FATNESS, A_SEED_POINT, A_POINTS, A_CONN, A_OFFSETS, A_TYPES,
    A_FACES, A_FACEOFFSETS, A_COUNT
};

/* Writes one DataArray element with a reserved offset; records where the
 * offset text goes. */
static void xml_array(FILE *fp, const char *indent, const char *type, const char *name,
                      int ncomp, long *offset_pos)
{
    fprintf(fp, "%s<DataArray type=\"%s\" Name=\"%s\"", indent, type, name);
    if (ncomp > 1)
        fprintf(fp, " NumberOfComponents=\"%d\"", ncomp);
    fputs(" format=\"appended\" offset=", fp);
    *offset_pos = ftell(fp);
    fprintf(fp, "%-*s/>\n", VTU_OFFSET_ROOM, "\"0\"");
}

/* ---- the writer ------------------------------------------------------ */

static int vtu_check_mesh(const vc_polymesh *m, const char *path, vc_error *err)
{
    if (m->n_cells < 0 || m->n_points < 0 || m->n_faces < 0)
        return vc_error_set(err, VC_EINPUT, "%s: mesh has negative sizes", path);
    if (m->n_cells > 0 && (!m->cell_offsets || !m->cell_faces || !m->face_offsets ||
                           !m->face_vertices || !m->face_owner))
        return vc_error_set(err, VC_EINPUT, "%s: mesh has no cell/face topology", path);
    if (m->n_points > 0 && !m->points)
        return vc_error_set(err, VC_EINPUT, "%s: mesh has no point coordinates", path);
    /* The cells in parallel (a pass over every face of every cell: most of
     * writing a large mesh when serial); the first bad one again below for
     * its message. */
    int64_t first_bad = m->n_cells;
#pragma omp parallel for schedule(static) reduction(min : first_bad) if (m->n_cells > 4096)
    for (int64_t c = 0; c < m->n_cells; ++c) {
        int ok = 1;
        for (int64_t k = m->cell_offsets[c]; k < m->cell_offsets[c + 1] && ok; ++k) {
            const int64_t f = m->cell_faces[k];
            if (f < 0 || f >= m->n_faces) {
                ok = 0;
                break;
            }
            for (int64_t i = m->face_offsets[f]; i < m->face_offsets[f + 1]; ++i)
                if (m->face_vertices[i] < 0 || m->face_vertices[i] >= m->n_points) {
                    ok = 0;
                    break;
                }
        }
        if (!ok && c < first_bad)
            first_bad = c;
    }
    for (int64_t c = first_bad; c < m->n_cells; ++c) {
        for (int64_t k = m->cell_offsets[c]; k < m->cell_offsets[c + 1]; ++k) {
            int64_t f = m->cell_faces[k];
            if (f < 0 || f >= m->n_faces)
                return vc_error_set(err, VC_EINPUT, "%s: cell %" PRId64
                                    " lists face %" PRId64 " out of range", path, c, f);
            for (int64_t i = m->face_offsets[f]; i < m->face_offsets[f + 1]; ++i) {
                int64_t v = m->face_vertices[i];
                if (v < 0 || v >= m->n_points)
                    return vc_error_set(err, VC_EINPUT, "%s: face %" PRId64
                                        " has vertex %" PRId64 " out of range", path, f, v);
            }
        }
    }
    return VC_OK;
}

/* ---- the cells' index streams, made in parallel ------------------------ */

/* A thread's scratch for cell_points: an open-addressing set of point ids. */
typedef struct point_set {
    int64_t *slot;
    int64_t cap; /* slots allocated */
} point_set;

/* The face-vertex entries of cell c (every face's points, counted again
 * where faces share them). */
static int64_t cell_entries(const vc_polymesh *m, int64_t c)
{
    int64_t n = 0;
    for (int64_t k = m->cell_offsets[c]; k < m->cell_offsets[c + 1]; ++k) {
        const int64_t f = m->cell_faces[k];
        n += m->face_offsets[f + 1] - m->face_offsets[f];
    }
    return n;
}

/* The distinct points of cell c in order of first appearance (faces in
 * the cell's order, each face's points in its stored order) to out when
 * not NULL; returns how many, or -1 when out of memory. A set per cell
 * rather than a stamp per point of the mesh, so that cells are done in
 * parallel without an array of all points per thread. */
static int64_t cell_points(const vc_polymesh *m, int64_t c, point_set *ps, int64_t *out)
{
    /* a table sized for this cell (not the largest one so far: it is
     * cleared for every cell) */
    const int64_t need = 2 * cell_entries(m, c) + 2;
    int64_t size = 64;
    while (size < need)
        size *= 2;
    if (ps->cap < size) {
        int64_t *q = realloc(ps->slot, sizeof(int64_t) * (size_t)size);
        if (!q)
            return -1;
        ps->slot = q;
        ps->cap = size;
    }
    const uint64_t mask = (uint64_t)size - 1;
    for (int64_t i = 0; i < size; ++i)
        ps->slot[i] = -1;
    int64_t n = 0;
    for (int64_t k = m->cell_offsets[c]; k < m->cell_offsets[c + 1]; ++k) {
        const int64_t f = m->cell_faces[k];
        for (int64_t i = m->face_offsets[f]; i < m->face_offsets[f + 1]; ++i) {
            const int64_t v = m->face_vertices[i];
            uint64_t h = ((uint64_t)v * 0x9E3779B97F4A7C15ull) >> 17;
            for (;; h++) {
                int64_t *e = &ps->slot[h & mask];
                if (*e == v)
                    break;
                if (*e < 0) {
                    *e = v;
                    if (out)
                        out[n] = v;
                    n++;
                    break;
                }
            }
        }
    }
    return n;
}

/* Index w bytes wide (4: Int32, 8: Int64) at dst[i]. */
static inline void put_index_at(unsigned char *dst, int64_t i, int64_t v, int w)
{
    if (w == 8) {
        memcpy(dst + 8 * i, &v, 8);
    } else {
        const int32_t x = (int32_t)v;
        memcpy(dst + 4 * i, &x, 4);
    }
}

/* Which stream a chunk of cells is made for. */
enum { STREAM_CONN, STREAM_FACES };

/* The indices of cells [c0, c1) of one stream into buf (from the cells'
 * ends in it, `end`), in parallel; 0, or -1 when out of memory. */
static int fill_cells(const vc_polymesh *m, int stream, const int64_t *end, int64_t c0,
                      int64_t c1, int w, unsigned char *buf, int threads)
{
    const int64_t base = c0 > 0 ? end[c0 - 1] : 0;
    int oom = 0;
#pragma omp parallel num_threads(threads) if (c1 - c0 > 256) reduction(| : oom)
    {
        point_set ps = {NULL, 0};
        int64_t *pts = NULL, pts_cap = 0;
#pragma omp for schedule(static)
        for (int64_t c = c0; c < c1; ++c) {
            int64_t at = (c > 0 ? end[c - 1] : 0) - base;
            if (stream == STREAM_CONN) {
                const int64_t ne = cell_entries(m, c);
                if (pts_cap < ne) {
                    int64_t *q = realloc(pts, sizeof(int64_t) * (size_t)(ne + 16));
                    if (!q) {
                        oom = 1;
                        continue;
                    }
                    pts = q;
                    pts_cap = ne + 16;
                }
                const int64_t n = cell_points(m, c, &ps, pts);
                if (n < 0) {
                    oom = 1;
                    continue;
                }
                for (int64_t i = 0; i < n; ++i)
                    put_index_at(buf, at + i, pts[i], w);
                continue;
            }
            /* faces: [nfaces, n0, ids..., n1, ids...], outward for the cell */
            put_index_at(buf, at++, m->cell_offsets[c + 1] - m->cell_offsets[c], w);
            for (int64_t k = m->cell_offsets[c]; k < m->cell_offsets[c + 1]; ++k) {
                const int64_t f = m->cell_faces[k];
                const int64_t b = m->face_offsets[f], e = m->face_offsets[f + 1];
                put_index_at(buf, at++, e - b, w);
                if (m->face_owner[f] == c)
                    for (int64_t i = b; i < e; ++i)
                        put_index_at(buf, at++, m->face_vertices[i], w);
                else
                    for (int64_t i = e - 1; i >= b; --i)
                        put_index_at(buf, at++, m->face_vertices[i], w);
            }
        }
        free(ps.slot);
        free(pts);
    }
    return oom ? -1 : 0;
}

/* One stream of all cells, in chunks of about CHUNK_BYTES made in
 * parallel and then fed to the stream (which compresses its blocks in
 * parallel): the serial per-index loops were most of writing a large
 * mesh (1M cells: 5 s). */
#define CHUNK_BYTES ((int64_t)8 << 20)
static int put_cells(vtu_stream *s, const vc_polymesh *m, int stream, const int64_t *end, int w,
                     unsigned char **buf, int64_t *buf_cap)
{
    const int64_t nc = m->n_cells;
    for (int64_t c0 = 0; c0 < nc;) {
        const int64_t base = c0 > 0 ? end[c0 - 1] : 0;
        int64_t c1 = c0 + 1;
        /* at least one cell, then while the chunk stays under the bound */
        while (c1 < nc && (end[c1] - base) * w <= CHUNK_BYTES)
            c1++;
        const int64_t bytes = (end[c1 - 1] - base) * w;
        if (*buf_cap < bytes) {
            unsigned char *q = realloc(*buf, (size_t)bytes);
            if (!q)
                return -1;
            *buf = q;
            *buf_cap = bytes;
        }
        if (fill_cells(m, stream, end, c0, c1, w, *buf, s->n_zc > 0 ? s->n_zc : 1))
            return -1;
        vtu_put(s, *buf, (size_t)bytes);
        c0 = c1;
    }
    return 0;
}

int vc_write_vtu(const vc_polymesh *m, const char *path, vc_vtu_encoding enc,
                 vc_error *err)
{
    if (!m || !path)
        return vc_error_set(err, VC_EPARAM, "vc_write_vtu: NULL argument");
    if (enc != VC_VTU_RAW && enc != VC_VTU_ZLIB)
        return vc_error_set(err, VC_EPARAM, "%s: unknown VTU encoding %d", path, (int)enc);
    int rc = vtu_check_mesh(m, path, err);
    if (rc)
        return rc;

    const int64_t nc = m->n_cells, np = m->n_points;

    /* Pass 1: per-cell ends in connectivity (distinct points) and in faces,
     * counted in parallel, then added up. */
    int64_t *conn_end = malloc(sizeof(int64_t) * (size_t)(nc > 0 ? nc : 1));
    int64_t *face_end = malloc(sizeof(int64_t) * (size_t)(nc > 0 ? nc : 1));
    if (!conn_end || !face_end) {
        free(conn_end);
        free(face_end);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    }
    int count_oom = 0;
#pragma omp parallel if (nc > 256) reduction(| : count_oom)
    {
        point_set ps = {NULL, 0};
#pragma omp for schedule(static)
        for (int64_t c = 0; c < nc; ++c) {
            const int64_t n = cell_points(m, c, &ps, NULL);
            count_oom |= n < 0;
            conn_end[c] = n;
            face_end[c] = 1 + (m->cell_offsets[c + 1] - m->cell_offsets[c]) + cell_entries(m, c);
        }
        free(ps.slot);
    }
    if (count_oom) {
        free(conn_end);
        free(face_end);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    }
    int64_t nconn = 0, nfacestream = 0;
    for (int64_t c = 0; c < nc; ++c) {
        nconn += conn_end[c];
        nfacestream += face_end[c];
        conn_end[c] = nconn;
        face_end[c] = nfacestream;
    }
    /* Indices as Int32 when every one fits (VTK reads either): half the
     * bytes to compress and write, the most of a large mesh's writing. */
    const int iw = np <= INT32_MAX && nconn <= INT32_MAX && nfacestream <= INT32_MAX ? 4 : 8;
    const char *itype = iw == 4 ? "Int32" : "Int64";

    vc_tmpfile t;
    rc = vc_tmpfile_open(&t, path, err);
    if (rc) {
        free(conn_end);
        free(face_end);
        return rc;
    }
    FILE *fp = t.fp;

    /* XML header */
    long opos[A_COUNT];
    fputs("<?xml version=\"1.0\"?>\n", fp);
    fprintf(fp, "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"%s\""
                " header_type=\"UInt64\"%s>\n", VTU_BYTE_ORDER,
            enc == VC_VTU_ZLIB ? " compressor=\"vtkZLibDataCompressor\"" : "");
    fputs("  <UnstructuredGrid>\n", fp);
    fprintf(fp, "    <Piece NumberOfPoints=\"%" PRId64 "\" NumberOfCells=\"%" PRId64 "\">\n",
            np, nc);
    fputs("      <CellData Scalars=\"region\">\n", fp);
    const char *in8 = "        ";
    xml_array(fp, in8, "Int32", "region", 1, &opos[A_REGION]);
    xml_array(fp, in8, "Int64", "seed", 1, &opos[A_SEED]);
    xml_array(fp, in8, "Float64", "volume", 1, &opos[A_VOLUME]);
    opos[A_FATNESS] = -1; /* optional: only when the mesh carries it */
    if (m->cell_fatness)
        xml_array(fp, in8, "Float64", "fatness", 1, &opos[A_FATNESS]);
    /* each cell's seed: the two-point-flux connection runs between them */
    const int seed_points = m->seed_xyz && m->cell_seed;
    opos[A_SEED_POINT] = -1;
    if (seed_points)
        xml_array(fp, in8, "Float64", "seed_point", 3, &opos[A_SEED_POINT]);
    fputs("      </CellData>\n", fp);
    fputs("      <Points>\n", fp);
    xml_array(fp, in8, "Float64", "Points", 3, &opos[A_POINTS]);
    fputs("      </Points>\n", fp);
    fputs("      <Cells>\n", fp);
    xml_array(fp, in8, itype, "connectivity", 1, &opos[A_CONN]);
    xml_array(fp, in8, itype, "offsets", 1, &opos[A_OFFSETS]);
    xml_array(fp, in8, "UInt8", "types", 1, &opos[A_TYPES]);
    xml_array(fp, in8, itype, "faces", 1, &opos[A_FACES]);
    xml_array(fp, in8, itype, "faceoffsets", 1, &opos[A_FACEOFFSETS]);
    fputs("      </Cells>\n", fp);
    fputs("    </Piece>\n", fp);
    fputs("  </UnstructuredGrid>\n", fp);
    fputs("  <AppendedData encoding=\"raw\">\n   _", fp);

    vtu_stream s;
    uint64_t off[A_COUNT];
    int src = vtu_stream_init(&s, fp, enc);
    if (src) {
        vtu_stream_free(&s);
        vc_tmpfile_discard(&t);
        free(conn_end);
        free(face_end);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    }
    if (ferror(fp))
        s.err_no = errno ? errno : EIO;
    s.data_start = ftell(fp);
    if (s.data_start < 0 && !s.err_no)
        s.err_no = errno ? errno : EIO;

    const uint64_t unc = (uint64_t)nc;
    /* cell data */
    off[A_REGION] = vtu_begin(&s, 4 * unc);
    if (m->cell_region)
        vtu_put(&s, m->cell_region, 4 * (size_t)nc);
    else
        for (int64_t c = 0; c < nc; ++c) {
            int32_t r = 1;
            vtu_put(&s, &r, 4);
        }
    if (!src) src = vtu_end(&s);

    off[A_SEED] = vtu_begin(&s, 8 * unc);
    if (m->cell_seed)
        vtu_put(&s, m->cell_seed, 8 * (size_t)nc);
    else
        for (int64_t c = 0; c < nc; ++c)
            vtu_put_i64(&s, c);
    if (!src) src = vtu_end(&s);

    off[A_VOLUME] = vtu_begin(&s, 8 * unc);
    if (m->cell_volume)
        vtu_put(&s, m->cell_volume, 8 * (size_t)nc);
    else
        for (int64_t c = 0; c < nc; ++c) {
            double v = 0.0;
            vtu_put(&s, &v, 8);
        }
    if (!src) src = vtu_end(&s);

    off[A_FATNESS] = 0;
    if (m->cell_fatness) {
        off[A_FATNESS] = vtu_begin(&s, 8 * unc);
        vtu_put(&s, m->cell_fatness, 8 * (size_t)nc);
        if (!src) src = vtu_end(&s);
    }

    off[A_SEED_POINT] = 0;
    if (seed_points) {
        off[A_SEED_POINT] = vtu_begin(&s, 24 * unc);
        for (int64_t c = 0; c < nc; ++c)
            vtu_put(&s, m->seed_xyz + 3 * m->cell_seed[c], 24);
        if (!src) src = vtu_end(&s);
    }

    /* points */
    off[A_POINTS] = vtu_begin(&s, 24 * (uint64_t)np);
    vtu_put(&s, m->points, 24 * (size_t)np);
    if (!src) src = vtu_end(&s);

    /* connectivity: distinct points of each cell, in order of appearance */
    unsigned char *chunk = NULL;
    int64_t chunk_cap = 0;
    off[A_CONN] = vtu_begin(&s, (uint64_t)iw * (uint64_t)nconn);
    if (put_cells(&s, m, STREAM_CONN, conn_end, iw, &chunk, &chunk_cap))
        s.zerr = 1;
    if (!src) src = vtu_end(&s);

    off[A_OFFSETS] = vtu_begin(&s, (uint64_t)iw * unc);
    for (int64_t c = 0; c < nc; ++c)
        vtu_put_index(&s, conn_end[c], iw);
    if (!src) src = vtu_end(&s);

    off[A_TYPES] = vtu_begin(&s, unc);
    {
        unsigned char ty[4096];
        memset(ty, VTK_POLYHEDRON_TYPE, sizeof ty);
        for (int64_t c = 0; c < nc; c += (int64_t)sizeof ty) {
            size_t k = nc - c < (int64_t)sizeof ty ? (size_t)(nc - c) : sizeof ty;
            vtu_put(&s, ty, k);
        }
    }
    if (!src) src = vtu_end(&s);

    /* faces: [nfaces, n0, ids..., n1, ids...] per cell, outward for the cell */
    off[A_FACES] = vtu_begin(&s, (uint64_t)iw * (uint64_t)nfacestream);
    if (put_cells(&s, m, STREAM_FACES, face_end, iw, &chunk, &chunk_cap))
        s.zerr = 1;
    free(chunk);
    if (!src) src = vtu_end(&s);

    off[A_FACEOFFSETS] = vtu_begin(&s, (uint64_t)iw * unc);
    for (int64_t c = 0; c < nc; ++c)
        vtu_put_index(&s, face_end[c], iw);
    if (!src) src = vtu_end(&s);

    {
        static const char tail[] = "\n  </AppendedData>\n</VTKFile>\n";
        vtu_fwrite(&s, tail, sizeof tail - 1);
    }

    /* patch the offsets in the XML header */
    if (!src && !s.err_no) {
        for (int a = 0; a < A_COUNT && !s.err_no; ++a) {
            if (opos[a] < 0)
                continue;
            char txt[VTU_OFFSET_ROOM + 1];
            snprintf(txt, sizeof txt, "\"%" PRIu64 "\"", off[a]);
            size_t n = strlen(txt);
            if (fseek(fp, opos[a], SEEK_SET) != 0)
                s.err_no = errno ? errno : EIO;
            else
                vtu_fwrite(&s, txt, n);
        }
    }
    int write_errno = s.err_no;
    vtu_stream_free(&s);
    free(conn_end);
    free(face_end);

    if (src == VC_EINTERNAL) {
        vc_tmpfile_discard(&t);
        return vc_error_set(err, VC_EINTERNAL, "%s: array size mismatch in VTU writer", path);
    }
    if (src == VC_ENOMEM) {
        vc_tmpfile_discard(&t);
        return vc_error_set(err, VC_ENOMEM, "%s: zlib compression failed (out of memory)",
                            path);
    }
    if (write_errno) {
        vc_tmpfile_discard(&t);
        return vc_error_set(err, VC_EIO, "%s: cannot write: %s", path, strerror(write_errno));
    }
    return vc_tmpfile_commit(&t, err);
}
