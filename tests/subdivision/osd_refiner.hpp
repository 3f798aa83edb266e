// SPDX-License-Identifier: MIT
// OpenSubdiv Far as an oracle (tests and bench/cifs_bench_mesh): a uniform refiner for a cifs::Mesh
// and a vertex type for its primvar refinement and stencil tables.
#pragma once

#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <memory>
#include <vector>

#include "cifs/mesh.hpp"

namespace cifs_test {

struct OsdVertex {
  double p[3];
  void Clear(void* = nullptr) { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(const OsdVertex& s, double w) {
    p[0] += w * s.p[0];
    p[1] += w * s.p[1];
    p[2] += w * s.p[2];
  }
};

/// The mesh's faces refined `levels` times uniformly by OpenSubdiv; `full_topology` keeps the last
/// level's adjacency, which PrimvarRefiner::Limit needs.
inline std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> osd_refiner(
    const cifs::Mesh& m, OpenSubdiv::Sdc::SchemeType type,
    OpenSubdiv::Sdc::Options::VtxBoundaryInterpolation boundary, int levels, bool full_topology = false) {
  namespace Far = OpenSubdiv::Far;
  std::vector<int> counts;
  for (std::size_t f = 0; f < cifs::face_count(m); ++f)
    counts.push_back(static_cast<int>(cifs::face(m, f).size()));
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(m.vertices.rows());
  desc.numFaces = static_cast<int>(counts.size());
  desc.numVertsPerFace = counts.data();
  desc.vertIndicesPerFace = m.face_vertices.data();
  OpenSubdiv::Sdc::Options so;
  so.SetVtxBoundaryInterpolation(boundary);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(desc, Factory::Options(type, so)));
  Far::TopologyRefiner::UniformOptions uniform(levels);
  uniform.fullTopologyInLastLevel = full_topology;
  if (refiner) refiner->RefineUniform(uniform);
  return refiner;
}

}  // namespace cifs_test
