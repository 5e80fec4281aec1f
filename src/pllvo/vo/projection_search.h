#pragma once
// Association of a new keyframe's features with map points of recent keyframes by projection
// (ORB-SLAM's "search by projection"). KLT tracks and matches with the previous keyframe only
// link a feature to a point that was followed without a break; a point whose track dropped for
// one frame was otherwise lost for good and the same corner triangulated again, with a new
// scale error, from a short baseline. Projection search re-attaches it to its old point, so
// points live longer and the bundle adjustment holds the scale over more keyframes.
#include <vector>

#include "pllvo/geometry/pose.h"
#include "pllvo/vo/geometry_adapter.h"
#include "pllvo/vo/map.h"
#include "pllvo/vo/point_frontend.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

/// For each feature of `features` seen from `T_world_cam` whose entry in `ids` is kNoId: the
/// map point (seen by one of `keyframes`, not in `ids` already) whose projection lies within
/// the radius and whose descriptor (from its newest observation) is the nearest within the
/// limits and passes the ratio test; kNoId otherwise. A point goes to one feature at most,
/// the nearest in descriptor space.
std::vector<Id> search_by_projection(const MapData& map, const std::vector<Id>& keyframes, const Pinhole& camera,
                                     const geometry::Pose& T_world_cam, const PointFeatures& features,
                                     const std::vector<Id>& ids, const ProjectionSearchConfig& config);

}  // namespace pllvo::vo
