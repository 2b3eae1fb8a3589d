#include "ispars/reference/fcl_checker.hpp"

#include <fcl/fcl.h>
#include <Eigen/Geometry>

namespace ispars::reference {

struct FclCollisionChecker::Model {
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> bvh;
  fcl::Transform3d identity = fcl::Transform3d::Identity();
};

FclCollisionChecker::FclCollisionChecker(const scene_files::TriangleMesh& mesh, Aabb bounds, double robot_radius)
    : model_(std::make_unique<Model>()), bounds_(bounds), radius_(robot_radius) {
  std::vector<fcl::Vector3d> vertices;
  vertices.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) vertices.push_back(v.cast<double>());
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(mesh.triangle_count());
  for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  model_->bvh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  model_->bvh->beginModel();
  model_->bvh->addSubModel(vertices, triangles);
  model_->bvh->endModel();
}

FclCollisionChecker::~FclCollisionChecker() = default;

namespace {

bool collides(const fcl::CollisionGeometryd& shape, const fcl::Transform3d& pose, const fcl::CollisionGeometryd& mesh,
              const fcl::Transform3d& mesh_pose) {
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  return fcl::collide(&shape, pose, &mesh, mesh_pose, request, result) > 0;
}

}  // namespace

bool FclCollisionChecker::point_valid(const Vec3& q) const {
  if (!bounds_.contains(q)) return false;
  const fcl::Sphered sphere(radius_);
  fcl::Transform3d pose = fcl::Transform3d::Identity();
  pose.translation() = q;
  return !collides(sphere, pose, *model_->bvh, model_->identity);
}

bool FclCollisionChecker::segment_valid(const Vec3& a, const Vec3& b) const {
  if (!bounds_.contains(a) || !bounds_.contains(b)) return false;
  const Vec3 axis = b - a;
  const double length = axis.norm();
  if (length == 0.0) return point_valid(a);
  // FCL's capsule is centred at the origin along local z.
  const fcl::Capsuled capsule(radius_, length);
  fcl::Transform3d pose = fcl::Transform3d::Identity();
  pose.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), axis / length).toRotationMatrix();
  pose.translation() = 0.5 * (a + b);
  return !collides(capsule, pose, *model_->bvh, model_->identity);
}

}  // namespace ispars::reference
