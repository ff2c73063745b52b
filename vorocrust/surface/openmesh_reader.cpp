/* OpenMesh adapter: reads any format OpenMesh knows into a vc_soup.
 *
 * Choice of reader (see surface.c): the project's own C readers
 * (read_obj.c, read_off.c, read_stl.c, read_ply.c) are the reader of record
 * for OBJ, OFF, STL and PLY, and this adapter reads the same files a
 * second time when VC_READER_OPENMESH is asked for (to cross-check the
 * readers), only after our own reader has accepted them: OpenMesh's readers
 * trust header counts (gigabytes reserved for a 100-byte binary OFF). No
 * other format goes to OpenMesh: its .om reader loops over the header's
 * counts (2.7 GB and 15 s for a 118-byte file) and aborts on an assertion
 * when a chunk header is malformed (a 1-D position chunk), and no reader of
 * ours validates .om first. Measured with
 * OpenMesh 9.0, its OBJ and OFF readers go through float (an input of
 * 0.1234567890123 comes back as 0.12345679104), skip a vertex line holding
 * "nan" without notice (shifting every later index), drop faces that
 * repeat a vertex ("f 1 1 2"), and return uninitialised indices after an
 * "inf" coordinate in OFF; a validating reader cannot be built on that.
 *
 * Faces are recorded as the reader hands them to the importer, before
 * OpenMesh's halfedge mesh sees them: the halfedge structure refuses
 * faces on an edge already used by two faces (non-manifold interfaces of
 * multi-material inputs) and inconsistently oriented faces, and ImporterT
 * then re-adds them on duplicated vertices. Recording first keeps the
 * input's connectivity exactly. OpenMesh's log streams are silenced. */
#include "surface/surface_internal.h"

/* OpenMesh's VectorT leaves its components uninitialised on purpose; GCC 12
 * warns about that inside OpenMesh's own property code. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <vector>

namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
};
typedef OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits> Mesh;

/* An importer that records vertices and faces in file order and still
 * forwards them to ImporterT, so that readers asking for the mesh's
 * handles get valid ones. Our vertex index i maps to the mesh handle
 * mesh_vertex[i] (they differ once ImporterT duplicated vertices). */
class RecordingImporter : public OpenMesh::IO::ImporterT<Mesh> {
public:
    explicit RecordingImporter(Mesh &m) : OpenMesh::IO::ImporterT<Mesh>(m) {}

    std::vector<double> xyz;
    std::vector<int64_t> face_offsets{0};
    std::vector<int64_t> face_indices;

    OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f &p) override
    {
        return record(OpenMesh::Vec3d(p[0], p[1], p[2]));
    }
    OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3d &p) override
    {
        return record(p);
    }
    OpenMesh::FaceHandle add_face(const VHandles &v) override
    {
        VHandles mapped;
        mapped.reserve(v.size());
        for (const OpenMesh::VertexHandle &h : v) {
            face_indices.push_back(h.idx());
            int i = h.idx();
            mapped.push_back(i >= 0 && (size_t)i < mesh_vertex.size() ? mesh_vertex[i]
                                                                     : OpenMesh::VertexHandle());
        }
        face_offsets.push_back((int64_t)face_indices.size());
        return OpenMesh::IO::ImporterT<Mesh>::add_face(mapped);
    }

private:
    std::vector<OpenMesh::VertexHandle> mesh_vertex;

    OpenMesh::VertexHandle record(const OpenMesh::Vec3d &p)
    {
        xyz.push_back(p[0]);
        xyz.push_back(p[1]);
        xyz.push_back(p[2]);
        mesh_vertex.push_back(OpenMesh::IO::ImporterT<Mesh>::add_vertex(p));
        return OpenMesh::VertexHandle((int)(mesh_vertex.size() - 1));
    }
};

void silence_openmesh()
{
    ::omerr().disable();
    ::omlog().disable();
    ::omout().disable();
}

} // namespace

extern "C" int vc_openmesh_read(const char *path, const char *name, vc_soup *s, vc_error *err)
{
    silence_openmesh();
    try {
        Mesh mesh;
        RecordingImporter imp(mesh);
        OpenMesh::IO::Options opt;
        if (!OpenMesh::IO::IOManager().read(path, imp, opt))
            return vc_error_set(err, VC_EFORMAT, "%s: OpenMesh could not read the file", name);
        const size_t nv = imp.xyz.size() / 3, nf = imp.face_offsets.size() - 1;
        s->nv = s->cap_v = (int64_t)nv;
        s->nf = s->cap_f = (int64_t)nf;
        s->ni = s->cap_i = (int64_t)imp.face_indices.size();
        s->xyz = (double *)std::malloc((nv ? nv : 1) * 3 * sizeof(double));
        s->off = (int64_t *)std::malloc((nf + 1) * sizeof(int64_t));
        s->idx = (int64_t *)std::malloc((s->ni ? s->ni : 1) * sizeof(int64_t));
        if (!s->xyz || !s->off || !s->idx) {
            vc_soup_free(s);
            return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
        }
        if (nv)
            std::memcpy(s->xyz, imp.xyz.data(), nv * 3 * sizeof(double));
        std::memcpy(s->off, imp.face_offsets.data(), (nf + 1) * sizeof(int64_t));
        if (s->ni)
            std::memcpy(s->idx, imp.face_indices.data(), (size_t)s->ni * sizeof(int64_t));
        s->cap_f = (int64_t)nf + 1;
        return 0;
    } catch (const std::bad_alloc &) {
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
    } catch (const std::exception &e) {
        return vc_error_set(err, VC_EFORMAT, "%s: OpenMesh failed: %s", name, e.what());
    } catch (...) {
        return vc_error_set(err, VC_EFORMAT, "%s: OpenMesh failed", name);
    }
}
