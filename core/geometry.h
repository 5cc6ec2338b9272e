#pragma once
// Small geometric value types shared by every layer. Right-handed world frame, Z up, metres.
#include <Eigen/Geometry>

namespace rfidray {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;  // Eigen stores (x, y, z, w); our CSV writes q1..q4 = x, y, z, w.

struct Pose {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();

  // Maps a point given in this pose's frame to the parent frame.
  Vec3 transform_point(const Vec3& local) const { return position + orientation * local; }
  // Maps a direction given in the parent frame into this pose's frame.
  Vec3 to_local_direction(const Vec3& world_dir) const { return orientation.conjugate() * world_dir; }
  Pose compose(const Pose& child) const {
    return Pose{transform_point(child.position), (orientation * child.orientation).normalized()};
  }
  bool operator==(const Pose& o) const {
    return position == o.position && orientation.coeffs() == o.orientation.coeffs();
  }
};

inline bool all_finite(const Vec3& v) { return v.allFinite(); }

}  // namespace rfidray
