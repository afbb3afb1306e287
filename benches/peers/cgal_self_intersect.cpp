// The client check of "no face crosses another": CGAL's
// Polygon_mesh_processing::self_intersections (exact predicates) on a mesh
// read from an OFF file, triangulated first. Faces that share a vertex or an
// edge and meet nowhere else do not count; faces that touch without sharing
// (shells meeting at a point) do.
//
//   cgal_self_intersect IN.off
//
// Prints `triangles T pairs P closed C` (P: intersecting pairs of triangles, C: 1 if closed).
// Built by the tests (tests/mesh) with
//   g++ -O2 -std=c++17 cgal_self_intersect.cpp -o cgal_self_intersect -lgmp -lmpfr
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <iostream>
#include <iterator>
#include <utility>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel Kernel;
typedef CGAL::Surface_mesh<Kernel::Point_3> Mesh;
namespace PMP = CGAL::Polygon_mesh_processing;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: cgal_self_intersect IN.off\n";
    return 2;
  }
  Mesh mesh;
  if (!CGAL::IO::read_polygon_mesh(argv[1], mesh)) {
    std::cerr << "cannot read " << argv[1] << "\n";
    return 1;
  }
  PMP::triangulate_faces(mesh);
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  PMP::self_intersections(mesh, std::back_inserter(pairs));
  std::cout << "triangles " << mesh.number_of_faces() << " pairs " << pairs.size() << " closed "
            << (CGAL::is_closed(mesh) ? 1 : 0) << "\n";
  return 0;
}
