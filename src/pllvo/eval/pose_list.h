#pragma once
// The pose sequences the evaluation works on: T_world_x, one per associated stamp.
#include <vector>

#include <Eigen/Geometry>

namespace pllvo::eval {

using PoseList = std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>>;

}  // namespace pllvo::eval
