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
  if (!CGAL::IO::write_polygon_mesh(argv[4], mesh, CGAL::parameters::stream_precision(17))) {
    std::cerr << "cannot write " << argv[4] << "\n";
    return 1;
  }
  std::cout << best << "\n";
  return 0;
}
