// The Catmull-Clark peer of `bcifs surface --net`: OpenSubdiv's uniform
// refinement (Far::TopologyRefiner + PrimvarRefiner) of a mesh read from an
// OFF file, its last level written as OBJ.
//
//   osd_subdivide DEPTH IN.off OUT.obj [ROUNDS]
//
// Prints the best time (ms) over ROUNDS runs of refinement + interpolation.
// Built with: g++ -O2 -std=c++17 osd_subdivide.cpp -o osd_subdivide -losdCPU
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

struct Vertex {
  float p[3];
  void Clear(void* = nullptr) { p[0] = p[1] = p[2] = 0.0f; }
  void AddWithWeight(const Vertex& s, float w) {
    p[0] += w * s.p[0];
    p[1] += w * s.p[1];
    p[2] += w * s.p[2];
  }
};

int main(int argc, char** argv) {
  if (argc < 4) {
    std::cerr << "usage: osd_subdivide DEPTH IN.off OUT.obj [ROUNDS]\n";
    return 2;
  }
  const int depth = std::atoi(argv[1]);
  const int rounds = argc > 4 ? std::atoi(argv[4]) : 1;
  std::ifstream in(argv[2]);
  std::string header;
  int nv = 0, nf = 0, ne = 0;
  in >> header >> nv >> nf >> ne;
  std::vector<Vertex> coarse(nv);
  for (auto& v : coarse) in >> v.p[0] >> v.p[1] >> v.p[2];
  std::vector<int> counts(nf), indices;
  for (int f = 0; f < nf; ++f) {
    in >> counts[f];
    for (int i = 0; i < counts[f]; ++i) {
      int k;
      in >> k;
      indices.push_back(k);
    }
  }
  Far::TopologyDescriptor desc;
  desc.numVertices = nv;
  desc.numFaces = nf;
  desc.numVertsPerFace = counts.data();
  desc.vertIndicesPerFace = indices.data();
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;
  double best = 1e300;
  Far::TopologyRefiner* refiner = nullptr;
  std::vector<Vertex> verts;
  for (int r = 0; r < rounds; ++r) {
    delete refiner;
    auto start = std::chrono::steady_clock::now();
    refiner = Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, options));
    refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(depth));
    verts.assign(refiner->GetNumVerticesTotal(), Vertex());
    std::copy(coarse.begin(), coarse.end(), verts.begin());
    Vertex* src = verts.data();
    Far::PrimvarRefiner primvar(*refiner);
    for (int level = 1; level <= depth; ++level) {
      Vertex* dst = src + refiner->GetLevel(level - 1).GetNumVertices();
      primvar.Interpolate(level, src, dst);
      src = dst;
    }
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    best = ms < best ? ms : best;
  }
  const Far::TopologyLevel& last = refiner->GetLevel(depth);
  int first = refiner->GetNumVerticesTotal() - last.GetNumVertices();
  FILE* out = std::fopen(argv[3], "w");
  for (int v = 0; v < last.GetNumVertices(); ++v) {
    const float* p = verts[first + v].p;
    std::fprintf(out, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
  }
  for (int f = 0; f < last.GetNumFaces(); ++f) {
    Far::ConstIndexArray fv = last.GetFaceVertices(f);
    std::fprintf(out, "f");
    for (int i = 0; i < fv.size(); ++i) std::fprintf(out, " %d", fv[i] + 1);
    std::fprintf(out, "\n");
  }
  std::fclose(out);
  std::cout << best << "\n";
  return 0;
}
