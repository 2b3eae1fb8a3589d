#include "ispars/scene_files/triangle_mesh.hpp"

#include <cmath>
#include <ostream>
#include <string>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "ispars/params/input_error.hpp"

namespace ispars::scene_files {

Aabb TriangleMesh::bounds() const {
  if (triangles.empty()) return {};
  Aabb box{Vec3::Constant(INFINITY), Vec3::Constant(-INFINITY)};
  for (const auto& tri : triangles) {
    for (const auto index : tri) {
      const Vec3 p = vertices[index].cast<double>();
      box.min = box.min.cwiseMin(p);
      box.max = box.max.cwiseMax(p);
    }
  }
  return box;
}

double TriangleMesh::surface_area() const {
  double area = 0.0;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    area += 0.5 * (corner(t, 1) - corner(t, 0)).cross(corner(t, 2) - corner(t, 0)).norm();
  }
  return area;
}

void TriangleMesh::append(const TriangleMesh& other) {
  const auto offset = static_cast<std::uint32_t>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const auto& tri : other.triangles) {
    triangles.push_back({tri[0] + offset, tri[1] + offset, tri[2] + offset});
  }
}

void TriangleMesh::scale(double factor) {
  for (auto& v : vertices) v = (v.cast<double>() * factor).cast<float>();
}

namespace {

// Walks the node tree, applying each node's accumulated transform to its meshes' vertices.
void flatten_node(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, TriangleMesh& out) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    if (!(mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const auto offset = static_cast<std::uint32_t>(out.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      out.vertices.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;
      out.triangles.push_back({offset + face.mIndices[0], offset + face.mIndices[1], offset + face.mIndices[2]});
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    flatten_node(scene, *node.mChildren[c], transform, out);
  }
}

}  // namespace

TriangleMesh load_triangle_mesh(const std::filesystem::path& path, const std::string& field) {
  const std::string file = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    throw params::InputError(file, field, "mesh file does not exist");
  }
  if (std::filesystem::is_directory(path, ec)) {
    throw params::InputError(file, field, "is a directory, not a mesh file");
  }

  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                                          aiComponent_COLORS | aiComponent_TEXCOORDS |
                                                          aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
                                                          aiComponent_TEXTURES | aiComponent_LIGHTS |
                                                          aiComponent_CAMERAS | aiComponent_MATERIALS);
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // Robotics meshes are Z-up; never let the COLLADA importer rotate them to Y-up.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_RemoveComponent |
                         aiProcess_SortByPType | aiProcess_DropNormals;
  const aiScene* scene = importer.ReadFile(file, flags);
  if (scene == nullptr || scene->mRootNode == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    std::string why = importer.GetErrorString();
    if (why.empty()) why = "no mesh data";
    for (char& c : why) {
      if (c == '\n' || c == '\r') c = ' ';
    }
    throw params::InputError(file, field, "cannot read mesh: " + why);
  }

  TriangleMesh mesh;
  flatten_node(*scene, *scene->mRootNode, aiMatrix4x4{}, mesh);
  if (mesh.triangles.empty()) {
    throw params::InputError(file, field, "mesh contains no triangles");
  }
  for (const auto& v : mesh.vertices) {
    if (!v.allFinite()) throw params::InputError(file, field, "mesh has a non-finite vertex coordinate");
  }
  return mesh;
}

void write_obj(const TriangleMesh& mesh, std::ostream& out) {
  out.precision(9);
  for (const auto& v : mesh.vertices) out << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  for (const auto& t : mesh.triangles) {
    out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  }
}

}  // namespace ispars::scene_files
