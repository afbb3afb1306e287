// The peer of `bcifs surface --net`: CGAL's Subdivision_method_3 on a mesh
// read from an OFF file, written back as OFF with full precision.
//
//   cgal_subdivide (doo-sabin|catmull-clark|loop|sqrt3) DEPTH IN.off OUT.off [ROUNDS]
//
// Prints the best time (ms) over ROUNDS runs of the subdivision alone.
// Built by the tests (tests/mesh) and the bench script with
//   g++ -O2 -std=c++17 cgal_subdivide.cpp -o cgal_subdivide -lgmp -lmpfr
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/subdivision_method_3.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <chrono>
#include <fstream>
#include <map>
#include <vector>
#include <cstdlib>
#include <iostream>
#include <string>

typedef CGAL::Simple_cartesian<double> Kernel;
typedef CGAL::Surface_mesh<Kernel::Point_3> Mesh;

int main(int argc, char** argv) {
  if (argc < 5) {
    std::cerr << "usage: cgal_subdivide (doo-sabin|catmull-clark|loop|sqrt3) DEPTH IN.off OUT.off [ROUNDS]\n";
    return 2;
  }
  const std::string scheme = argv[1];
  const int depth = std::atoi(argv[2]);
  const int rounds = argc > 5 ? std::atoi(argv[5]) : 1;
  Mesh input;
  if (!CGAL::IO::read_polygon_mesh(argv[3], input)) {
    std::cerr << "cannot read " << argv[3] << "\n";
    return 1;
  }
  double best = 1e300;
  Mesh mesh;
  for (int r = 0; r < rounds; ++r) {
    mesh = input;
    auto start = std::chrono::steady_clock::now();
    if (scheme == "doo-sabin") {
      CGAL::Subdivision_method_3::DooSabin_subdivision(mesh, CGAL::parameters::number_of_iterations(depth));
    } else if (scheme == "catmull-clark") {
      CGAL::Subdivision_method_3::CatmullClark_subdivision(mesh, CGAL::parameters::number_of_iterations(depth));
    } else if (scheme == "loop") {
      CGAL::Subdivision_method_3::Loop_subdivision(mesh, CGAL::parameters::number_of_iterations(depth));
    } else if (scheme == "sqrt3") {
      CGAL::Subdivision_method_3::Sqrt3_subdivision(mesh, CGAL::parameters::number_of_iterations(depth));
    } else {
      std::cerr << "unknown scheme " << scheme << "\n";
      return 2;
    }
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    best = ms < best ? ms : best;
  }
  // Written by hand: CGAL's OFF printer asserts on the digons (two-sided
  // faces) that Doo-Sabin makes at interior vertices of valence 2.
  std::ofstream file(argv[4]);
  file.precision(17);
  file << "OFF\n" << mesh.number_of_vertices() << " " << mesh.number_of_faces() << " 0\n";
  std::map<Mesh::Vertex_index, std::size_t> index;
  for (Mesh::Vertex_index v : mesh.vertices()) {
    const Kernel::Point_3& p = mesh.point(v);
    file << p.x() << " " << p.y() << " " << p.z() << "\n";
    const std::size_t next = index.size();
    index[v] = next;
  }
  for (Mesh::Face_index f : mesh.faces()) {
    std::vector<std::size_t> corners;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) corners.push_back(index[v]);
    file << corners.size();
    for (std::size_t c : corners) file << " " << c;
    file << "\n";
  }
  if (!file) {
    std::cerr << "cannot write " << argv[4] << "\n";
    return 1;
  }
  std::cout << best << "\n";
  return 0;
}
