#include "engine/sim/mesh_loader.hpp"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "engine/core/error.hpp"

namespace sarmap::sim {
namespace {

void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, LoadedMesh& out) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const auto base = static_cast<std::uint32_t>(out.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      out.vertices.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines have no area
      for (unsigned k = 0; k < 3; ++k) out.indices.push_back(base + face.mIndices[k]);
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) collect(scene, *node.mChildren[c], transform, out);
}

}  // namespace

LoadedMesh load_mesh_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw Error(ErrorCode::Io, path.string() + ": mesh file not found");
  }
  Assimp::Importer importer;
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_SortByPType);
  if (scene == nullptr || scene->mRootNode == nullptr) {
    throw Error(ErrorCode::Io, path.string() + ": cannot read mesh: " + importer.GetErrorString());
  }
  LoadedMesh out;
  collect(*scene, *scene->mRootNode, aiMatrix4x4(), out);
  if (out.indices.empty()) {
    throw Error(ErrorCode::InvalidData, path.string() + ": mesh holds no triangle");
  }
  for (const Eigen::Vector3f& v : out.vertices) {
    if (!v.allFinite()) throw Error(ErrorCode::InvalidData, path.string() + ": mesh has a NaN or infinite vertex");
  }
  return out;
}

}  // namespace sarmap::sim
