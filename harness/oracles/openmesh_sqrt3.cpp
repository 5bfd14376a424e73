// pgt oracle: Kobbelt's sqrt(3) subdivision (SIGGRAPH 2000) as OpenMesh 9.0 implements it,
// OpenMesh::Subdivider::Uniform::Sqrt3T on a TriMesh_ArrayKernelT with double points.
// Boundaries follow Kobbelt's rule section 4 in iterations 2, 4, ... of each call (the parity
// restarts at attach). OpenMesh's OFF I/O rounds through float, so the mesh is built from the
// arrays of oracle_common.hpp instead.
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/Sqrt3T.hh>

#include "oracle_common.hpp"

namespace {

struct Traits : OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

struct Openmesh_backend {
    Mesh mesh;
    std::size_t max_valence = 0;

    void build(const pgt_oracle::Tri_mesh &in) {
        const std::size_t nv = in.vertex_count(), nf = in.face_count();
        mesh.reserve(nv, nv + nf, nf);
        std::vector<Mesh::VertexHandle> vh(nv);
        for (std::size_t v = 0; v < nv; ++v)
            vh[v] = mesh.add_vertex(Mesh::Point(in.xyz[3 * v], in.xyz[3 * v + 1], in.xyz[3 * v + 2]));
        std::vector<std::size_t> faces_at(nv, 0);
        for (std::size_t t = 0; t < nf; ++t) {
            const std::uint32_t *c = &in.tri[3 * t];
            const Mesh::FaceHandle f = mesh.add_face(vh[c[0]], vh[c[1]], vh[c[2]]);
            if (!f.is_valid())
                throw pgt_oracle::Face_error(
                    t, "OpenMesh cannot add it (complex edge or vertex, or inconsistent "
                    "orientation)");
            for (int k = 0; k < 3; ++k) max_valence = std::max(max_valence, ++faces_at[c[k]]);
        }
    }

    void subdivide(int k) {
        OpenMesh::Subdivider::Uniform::Sqrt3T<Mesh, double> sqrt3;
        // Sqrt3T looks up its smoothing weights in a table of 50 valences without a bounds
        // check. Interior valences never grow under sqrt(3), so sizing the table from the input
        // (valence <= incident faces + 1) covers every iteration.
        sqrt3.init_weights(std::max<std::size_t>(50, max_valence + 2));
        if (!sqrt3.attach(mesh)) throw std::runtime_error("OpenMesh Sqrt3T::attach failed");
        if (!sqrt3(static_cast<std::size_t>(k))) throw std::runtime_error("OpenMesh Sqrt3T failed");
        sqrt3.detach();
    }

    // Vertices in handle order skipping deleted ones (sqrt(3) deletes none), faces renumbered
    // through the same map.
    pgt_oracle::Tri_mesh extract() const {
        pgt_oracle::Tri_mesh out;
        const bool vstatus = mesh.has_vertex_status(), fstatus = mesh.has_face_status();
        std::vector<std::uint32_t> remap(mesh.n_vertices(), UINT32_MAX);
        out.xyz.reserve(3 * mesh.n_vertices());
        out.tri.reserve(3 * mesh.n_faces());
        std::uint32_t next = 0;
        for (std::size_t i = 0; i < mesh.n_vertices(); ++i) {
            const Mesh::VertexHandle v(static_cast<int>(i));
            if (vstatus && mesh.status(v).deleted()) continue;
            remap[i] = next++;
            const Mesh::Point &p = mesh.point(v);
            out.xyz.insert(out.xyz.end(), {p[0], p[1], p[2]});
        }
        for (std::size_t i = 0; i < mesh.n_faces(); ++i) {
            const Mesh::FaceHandle f(static_cast<int>(i));
            if (fstatus && mesh.status(f).deleted()) continue;
            int n = 0;
            for (Mesh::VertexHandle v : mesh.fv_range(f)) {
                if (++n > 3) throw std::runtime_error("OpenMesh produced a non-triangle face");
                out.tri.push_back(remap[static_cast<std::size_t>(v.idx())]);
            }
            if (n != 3) throw std::runtime_error("OpenMesh produced a face with fewer than 3 vertices");
        }
        return out;
    }
};

} // namespace

int main(int argc, char **argv) {
    // add_face reports complex edges on omerr; our own message says which face and line.
    omerr().disable();
    return pgt_oracle::run<Openmesh_backend>(argc, argv, "openmesh");
}
