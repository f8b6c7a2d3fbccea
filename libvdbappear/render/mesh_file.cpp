#include "libvdbappear/render/mesh_file.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <filesystem>
#include <stdexcept>

namespace vdbappear {

std::vector<Triangle> readMesh(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(path + ": no such mesh file");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_JoinIdenticalVertices |
                aiProcess_FindDegenerates | aiProcess_SortByPType);
  if (!scene) throw std::runtime_error(path + ": cannot read the mesh (" + importer.GetErrorString() + ")");
  std::vector<Triangle> triangles;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines
      Triangle t;
      for (int k = 0; k < 3; ++k) {
        const aiVector3D& v = mesh->mVertices[face.mIndices[k]];
        t[k] = Vec3(v.x, v.y, v.z);
      }
      triangles.push_back(t);
    }
  }
  if (triangles.empty()) throw std::runtime_error(path + ": the mesh has no triangles");
  return triangles;
}

}  // namespace vdbappear
