// The face-varying peer of `bcifs surface --net` with texture coordinates:
// OpenSubdiv's uniform refinement (Far::TopologyRefiner + PrimvarRefiner) of
// an OBJ mesh with `vt` texture coordinates, positions and one face-varying
// channel, face-varying boundaries linear (FVAR_LINEAR_BOUNDARIES, Blender's
// "Keep Boundaries"), mesh borders as B-spline curves (VTX_BOUNDARY_EDGE_ONLY).
// Its last level is written as OBJ: `v`, `vt`, `f v/vt`.
//
//   osd_uv catmark|loop DEPTH IN.obj OUT.obj
//
// Built with: g++ -O2 -std=c++17 osd_uv.cpp -o osd_uv -losdCPU
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

template <int N>
struct Point {
  double p[N];
  void Clear(void* = nullptr) {
    for (double& x : p) x = 0.0;
  }
  void AddWithWeight(const Point& s, double w) {
    for (int i = 0; i < N; ++i) p[i] += w * s.p[i];
  }
};

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: osd_uv catmark|loop DEPTH IN.obj OUT.obj\n";
    return 2;
  }
  const std::string scheme = argv[1];
  const int depth = std::atoi(argv[2]);
  std::ifstream in(argv[3]);
  std::vector<Point<3>> positions;
  std::vector<Point<2>> uvs;
  std::vector<int> counts, vertices, textures;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "v") {
      Point<3> v;
      words >> v.p[0] >> v.p[1] >> v.p[2];
      positions.push_back(v);
    } else if (key == "vt") {
      Point<2> t;
      words >> t.p[0] >> t.p[1];
      uvs.push_back(t);
    } else if (key == "f") {
      std::string corner;
      int n = 0;
      while (words >> corner) {
        int v = 0, t = 0;
        if (std::sscanf(corner.c_str(), "%d/%d", &v, &t) != 2) {
          std::cerr << "a corner without a texture index: " << corner << "\n";
          return 1;
        }
        vertices.push_back(v - 1);
        textures.push_back(t - 1);
        ++n;
      }
      counts.push_back(n);
    }
  }
  Sdc::SchemeType type = scheme == "loop" ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  options.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_BOUNDARIES);
  Far::TopologyDescriptor::FVarChannel channel;
  channel.numValues = static_cast<int>(uvs.size());
  channel.valueIndices = textures.data();
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(positions.size());
  desc.numFaces = static_cast<int>(counts.size());
  desc.numVertsPerFace = counts.data();
  desc.vertIndicesPerFace = vertices.data();
  desc.numFVarChannels = 1;
  desc.fvarChannels = &channel;
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  Far::TopologyRefiner* refiner = Factory::Create(desc, Factory::Options(type, options));
  if (!refiner) {
    std::cerr << "OpenSubdiv refuses the mesh\n";
    return 1;
  }
  refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(depth));
  std::vector<Point<3>> p(refiner->GetNumVerticesTotal());
  std::vector<Point<2>> t(refiner->GetNumFVarValuesTotal(0));
  std::copy(positions.begin(), positions.end(), p.begin());
  std::copy(uvs.begin(), uvs.end(), t.begin());
  Far::PrimvarRefinerReal<double> primvar(*refiner);
  Point<3>* src = p.data();
  Point<2>* tsrc = t.data();
  for (int level = 1; level <= depth; ++level) {
    Point<3>* dst = src + refiner->GetLevel(level - 1).GetNumVertices();
    Point<2>* tdst = tsrc + refiner->GetLevel(level - 1).GetNumFVarValues(0);
    primvar.Interpolate(level, src, dst);
    primvar.InterpolateFaceVarying(level, tsrc, tdst, 0);
    src = dst;
    tsrc = tdst;
  }
  const Far::TopologyLevel& last = refiner->GetLevel(depth);
  std::ofstream out(argv[4]);
  out.precision(17);
  for (int v = 0; v < last.GetNumVertices(); ++v) out << "v " << src[v].p[0] << " " << src[v].p[1] << " " << src[v].p[2] << "\n";
  for (int k = 0; k < last.GetNumFVarValues(0); ++k) out << "vt " << tsrc[k].p[0] << " " << tsrc[k].p[1] << "\n";
  for (int f = 0; f < last.GetNumFaces(); ++f) {
    Far::ConstIndexArray fv = last.GetFaceVertices(f), ft = last.GetFaceFVarValues(f, 0);
    out << "f";
    for (int i = 0; i < fv.size(); ++i) out << " " << fv[i] + 1 << "/" << ft[i] + 1;
    out << "\n";
  }
  delete refiner;
  return 0;
}
