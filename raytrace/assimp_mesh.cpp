#include "raytrace/assimp_mesh.h"

#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>

#include "core/error.h"

namespace rfidray {
namespace {

struct Walk {
  const aiScene* scene = nullptr;
  TriangleMesh out;
  std::vector<int32_t> material_slot;  // assimp material index → out.material_names index (−1: not yet)
  size_t skipped_faces = 0;

  uint32_t slot(unsigned material) {
    if (material_slot[material] < 0) {
      aiString name;
      scene->mMaterials[material]->Get(AI_MATKEY_NAME, name);
      std::string s = name.C_Str();
      if (s == AI_DEFAULT_MATERIAL_NAME) s.clear();  // assimp's stand-in when the file names none
      auto it = std::find(out.material_names.begin(), out.material_names.end(), s);
      material_slot[material] = static_cast<int32_t>(it - out.material_names.begin());
      if (it == out.material_names.end()) out.material_names.push_back(s);
    }
    return static_cast<uint32_t>(material_slot[material]);
  }

  void node(const aiNode* n, const aiMatrix4x4& parent) {
    const aiMatrix4x4 m = parent * n->mTransformation;
    for (unsigned i = 0; i < n->mNumMeshes; ++i) {
      const aiMesh* mesh = scene->mMeshes[n->mMeshes[i]];
      const uint32_t base = static_cast<uint32_t>(out.vertices.size());
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const aiVector3D p = m * mesh->mVertices[v];
        out.vertices.emplace_back(p.x, p.y, p.z);
      }
      const uint32_t mat = slot(mesh->mMaterialIndex);
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices != 3) {  // points and lines (triangulation already split polygons)
          ++skipped_faces;
          continue;
        }
        out.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
        out.triangle_material.push_back(mat);
      }
    }
    for (unsigned c = 0; c < n->mNumChildren; ++c) node(n->mChildren[c], m);
  }
};

}  // namespace

bool mesh_formats_available() { return true; }

TriangleMesh load_assimp_mesh(const std::filesystem::path& path, const std::string& ext,
                              std::vector<std::string>* warnings) {
  const std::string file = path.string();
  Assimp::Importer importer;
  // Drop normals, colours and texture coordinates before joining vertices: only positions matter here.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                                         aiComponent_COLORS | aiComponent_TEXCOORDS |
                                                         aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
                                                         aiComponent_TEXTURES | aiComponent_LIGHTS | aiComponent_CAMERAS);
  const aiScene* scene = importer.ReadFile(
      file, aiProcess_RemoveComponent | aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                aiProcess_ValidateDataStructure);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw InputError(file + ": cannot read mesh (" + std::string(importer.GetErrorString()) + ")");
  Walk walk;
  walk.scene = scene;
  walk.out.name = path.stem().string();
  walk.material_slot.assign(scene->mNumMaterials, -1);
  aiMatrix4x4 root;  // identity
  if (ext == ".dae") {
    // assimp put the file's unit scale and its up axis → Y-up turn in the root node; turn Y up to Z up
    // (x, y, z) → (x, −z, y).
    root = aiMatrix4x4(1, 0, 0, 0,
                       0, 0, -1, 0,
                       0, 1, 0, 0,
                       0, 0, 0, 1);
  }
  walk.node(scene->mRootNode, root);
  if (walk.skipped_faces > 0 && warnings)
    warnings->push_back(file + ": " + std::to_string(walk.skipped_faces) + " point/line primitives skipped (not surfaces)");
  if (walk.out.triangles.empty()) throw InputError(file + ": mesh has no triangles");
  return std::move(walk.out);
}

}  // namespace rfidray
