// SPDX-License-Identifier: MIT
// cifs — face-varying channels (UVs) refined with the faces under OpenSubdiv's face-varying
// interpolation rules (Sdc FVarLinearInterpolation; docs/subdivision-surfaces.md, "Face-varying data").
// Internal to the subdivision module.
#pragma once

#include <string>
#include <vector>

#include "cifs/mesh.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/topology.hpp"

namespace cifs::subdivision::detail {

/// How a vertex's value at a face corner is refined. A seam (an edge whose two faces give an end
/// different values) splits the faces around a vertex into spans, one per value; `smooth`: no seam at
/// the vertex (and the boundary rules leave it alone), the vertex's own mask applies to the values;
/// `corner`: the value stays; `crease`: ¾ of it and ⅛ of each value across the span's two bounding
/// edges (the cubic B-spline along the seam); `semi_sharp`: a corner until the sharpness of the
/// vertex or of an edge inside the span has decayed, then blended into the crease; `dependent`: the
/// same, by the sharpness of the vertex's other value (corners+1 and corners+2 sharpen both values
/// of a seam vertex together).
enum class ValueRule : unsigned char { smooth, corner, crease, semi_sharp, dependent };

/// A channel at one level, with the rules its values carry from level to level (OpenSubdiv's
/// FVarLevel value tags: inherited by the child values, not recomputed, so they are part of the
/// level's state: a semi-sharp value turns into a crease when its sharpness is gone, never back).
struct ChannelLevel {
  FaceVaryingChannel channel;
  std::vector<ValueRule> rules;  // per face corner: the rule of its vertex's value there
};

/// Refuses (InvalidInput starting with `who`) face-varying channels a scheme has no rule for: any
/// under Doo–Sabin and √3 (their faces are no split of the parent's), a rule other than `all` under
/// Butterfly, the rule set `blz` or on a non-manifold mesh.
void check_channels(const Mesh& mesh, MeshScheme scheme, const std::string& who, bool non_manifold);

/// check_channels, and a rule other than `all` refused for limits: the limit of smoothly refined
/// values is not built (linear values are their own limit).
void check_limit_channels(const Mesh& mesh, MeshScheme scheme, const std::string& who);
/// A channel at a refinement's last level, linearly (the rule `all`, or the bilinear scheme: what
/// check_limit_channels lets through).
FaceVaryingChannel linear_channel(const MeshRefinement& refinement, const FaceVaryingChannel& channel);

/// The first level's state: the rule of every vertex value from the channel's seams, the level's
/// sharpness (`features`) and the face-varying rule, boundary rule of `tags`.
ChannelLevel analyse_channel(const MeshTopology& t, const LevelFeatures& features, const MeshTags& tags,
                             FaceVaryingChannel channel);

/// One step of a primal scheme (Catmull–Clark, Loop, bilinear; Butterfly under the rule `all`):
/// child values in the order of the child vertices (a value per vertex value, one per edge or one
/// per side of a seam, one per face of the quad split), child corners in the order of the split.
/// `halves` as primal_step makes it (empty on a smooth level).
ChannelLevel refine_channel(MeshScheme scheme, const MeshTopology& t, const LevelFeatures& features,
                            const std::vector<double>& halves, const MeshTags& tags,
                            const ChannelLevel& level);

}  // namespace cifs::subdivision::detail
