// pgt oracle: Kobbelt's sqrt(3) subdivision (SIGGRAPH 2000) as CGAL 5.5 implements it,
// CGAL::Subdivision_method_3::Sqrt3_subdivision on a Surface_mesh of double points.
// Boundaries follow Kobbelt's rule section 4 in iterations 2, 4, ... of each call (the parity
// restarts per call). See oracle_common.hpp for the command line and output.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/subdivision_method_3.h>

#include "oracle_common.hpp"

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;

struct Cgal_backend {
    Mesh mesh;

    void build(const pgt_oracle::Tri_mesh &in) {
        const std::size_t nv = in.vertex_count(), nf = in.face_count();
        mesh.reserve(static_cast<Mesh::size_type>(nv), static_cast<Mesh::size_type>(nv + nf),
                     static_cast<Mesh::size_type>(nf));
        for (std::size_t v = 0; v < nv; ++v)
            mesh.add_vertex(Kernel::Point_3(in.xyz[3 * v], in.xyz[3 * v + 1], in.xyz[3 * v + 2]));
        for (std::size_t t = 0; t < nf; ++t) {
            const Mesh::Face_index f = mesh.add_face(Mesh::Vertex_index(in.tri[3 * t]),
                                                     Mesh::Vertex_index(in.tri[3 * t + 1]),
                                                     Mesh::Vertex_index(in.tri[3 * t + 2]));
            if (f == Mesh::null_face())
                throw pgt_oracle::Face_error(
                    t, "CGAL cannot add it (non-manifold edge or vertex, or inconsistent "
                    "orientation)");
        }
    }

    void subdivide(int k) {
        CGAL::Subdivision_method_3::Sqrt3_subdivision(
            mesh, CGAL::parameters::number_of_iterations(k));
    }

    // Vertices in index order skipping removed ones (sqrt(3) removes none, but a Surface_mesh
    // may hold garbage), faces renumbered through the same map.
    pgt_oracle::Tri_mesh extract() const {
        pgt_oracle::Tri_mesh out;
        std::vector<std::uint32_t> remap(mesh.num_vertices(), UINT32_MAX);
        out.xyz.reserve(3 * static_cast<std::size_t>(mesh.number_of_vertices()));
        out.tri.reserve(3 * static_cast<std::size_t>(mesh.number_of_faces()));
        std::uint32_t next = 0;
        for (Mesh::Vertex_index v : mesh.vertices()) {
            remap[v] = next++;
            const Kernel::Point_3 &p = mesh.point(v);
            out.xyz.insert(out.xyz.end(), {p.x(), p.y(), p.z()});
        }
        for (Mesh::Face_index f : mesh.faces()) {
            int n = 0;
            for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
                if (++n > 3) throw std::runtime_error("CGAL produced a non-triangle face");
                out.tri.push_back(remap[v]);
            }
            if (n != 3) throw std::runtime_error("CGAL produced a face with fewer than 3 vertices");
        }
        return out;
    }
};

} // namespace

int main(int argc, char **argv) { return pgt_oracle::run<Cgal_backend>(argc, argv, "cgal"); }
