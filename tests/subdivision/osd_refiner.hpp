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

/// OpenSubdiv's options for a mesh's tags.
inline OpenSubdiv::Sdc::Options osd_options(const cifs::MeshTags& tags) {
  using O = OpenSubdiv::Sdc::Options;
  O so;
  so.SetVtxBoundaryInterpolation(tags.boundary == cifs::BoundaryRule::none ? O::VTX_BOUNDARY_NONE
                                 : tags.boundary == cifs::BoundaryRule::edge_only
                                     ? O::VTX_BOUNDARY_EDGE_ONLY
                                     : O::VTX_BOUNDARY_EDGE_AND_CORNER);
  so.SetCreasingMethod(tags.crease_method == cifs::CreaseMethod::uniform ? O::CREASE_UNIFORM
                                                                         : O::CREASE_CHAIKIN);
  so.SetTriangleSubdivision(tags.triangles == cifs::TriangleRule::catmark ? O::TRI_SUB_CATMARK
                                                                          : O::TRI_SUB_SMOOTH);
  constexpr O::FVarLinearInterpolation fvar[] = {O::FVAR_LINEAR_NONE,          O::FVAR_LINEAR_CORNERS_ONLY,
                                                 O::FVAR_LINEAR_CORNERS_PLUS1, O::FVAR_LINEAR_CORNERS_PLUS2,
                                                 O::FVAR_LINEAR_BOUNDARIES,    O::FVAR_LINEAR_ALL};
  so.SetFVarLinearInterpolation(fvar[static_cast<int>(tags.face_varying)]);
  return so;
}

/// The mesh's faces refined `levels` times uniformly by OpenSubdiv under the mesh's tags (creases,
/// corners, holes, options; sharpness as float: give values that floats hold exactly) and with its
/// face-varying channels; `full_topology` keeps the last level's adjacency, which
/// PrimvarRefiner::Limit needs.
inline std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> osd_refiner(const cifs::Mesh& m,
                                                                     OpenSubdiv::Sdc::SchemeType type,
                                                                     int levels, bool full_topology = false) {
  namespace Far = OpenSubdiv::Far;
  std::vector<int> counts;
  for (std::size_t f = 0; f < cifs::face_count(m); ++f)
    counts.push_back(static_cast<int>(cifs::face(m, f).size()));
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(m.vertices.rows());
  desc.numFaces = static_cast<int>(counts.size());
  desc.numVertsPerFace = counts.data();
  desc.vertIndicesPerFace = m.face_vertices.data();
  std::vector<int> crease_pairs, corner_vertices;
  std::vector<float> crease_weights, corner_weights;
  for (const cifs::EdgeSharpness& c : m.tags.creases) {
    crease_pairs.insert(crease_pairs.end(), {c.a, c.b});
    crease_weights.push_back(static_cast<float>(c.sharpness));
  }
  for (const cifs::VertexSharpness& c : m.tags.corners) {
    corner_vertices.push_back(c.vertex);
    corner_weights.push_back(static_cast<float>(c.sharpness));
  }
  desc.numCreases = static_cast<int>(crease_weights.size());
  desc.creaseVertexIndexPairs = crease_pairs.data();
  desc.creaseWeights = crease_weights.data();
  desc.numCorners = static_cast<int>(corner_weights.size());
  desc.cornerVertexIndices = corner_vertices.data();
  desc.cornerWeights = corner_weights.data();
  desc.numHoles = static_cast<int>(m.tags.holes.size());
  desc.holeIndices = m.tags.holes.data();
  std::vector<Far::TopologyDescriptor::FVarChannel> channels;
  for (const cifs::FaceVaryingChannel& c : m.face_varying) {
    Far::TopologyDescriptor::FVarChannel channel;
    channel.numValues = static_cast<int>(c.values.rows());
    channel.valueIndices = c.indices.data();
    channels.push_back(channel);
  }
  desc.numFVarChannels = static_cast<int>(channels.size());
  desc.fvarChannels = channels.data();
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(
      Factory::Create(desc, Factory::Options(type, osd_options(m.tags))));
  Far::TopologyRefiner::UniformOptions uniform(levels);
  uniform.fullTopologyInLastLevel = full_topology;
  if (refiner) refiner->RefineUniform(uniform);
  return refiner;
}

/// The mesh with another boundary rule.
inline cifs::Mesh with_boundary(cifs::Mesh m, cifs::BoundaryRule rule) {
  m.tags.boundary = rule;
  return m;
}

}  // namespace cifs_test
