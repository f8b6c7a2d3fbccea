#include "libvdbappear/render/mesh_file.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <filesystem>
#include <stdexcept>

namespace vdbappear {

namespace {

const aiScene* importMesh(Assimp::Importer& importer, const std::string& path, unsigned extra_steps = 0) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(path + ": no such mesh file");
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_JoinIdenticalVertices |
                aiProcess_FindDegenerates | aiProcess_SortByPType | extra_steps);
  if (!scene) throw std::runtime_error(path + ": cannot read the mesh (" + importer.GetErrorString() + ")");
  return scene;
}

Vec3 vec3Of(const aiVector3D& v) { return {v.x, v.y, v.z}; }

}  // namespace

std::vector<Triangle> readMesh(const std::string& path) {
  Assimp::Importer importer;
  const aiScene* scene = importMesh(importer, path);
  std::vector<Triangle> triangles;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines
      Triangle t;
      for (int k = 0; k < 3; ++k) {
        t[k] = vec3Of(mesh->mVertices[face.mIndices[k]]);
      }
      triangles.push_back(t);
    }
  }
  if (triangles.empty()) throw std::runtime_error(path + ": the mesh has no triangles");
  return triangles;
}

std::vector<UvTriangle> readUvMesh(const std::string& path) {
  Assimp::Importer importer;
  const aiScene* scene = importMesh(importer, path, aiProcess_GenSmoothNormals);
  std::vector<UvTriangle> triangles;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (mesh->mPrimitiveTypes != aiPrimitiveType_TRIANGLE) continue;  // points and lines
    if (!mesh->HasTextureCoords(0))
      throw std::runtime_error(path + ": the mesh has no texture coordinates (UVs), which a displacement map over it needs");
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      UvTriangle t;
      for (int k = 0; k < 3; ++k) {
        const unsigned v = face.mIndices[k];
        t.position[k] = vec3Of(mesh->mVertices[v]);
        t.normal[k] = mesh->HasNormals() ? vec3Of(mesh->mNormals[v]).normalized() : Vec3::Zero();
        t.uv[k] = Point2(mesh->mTextureCoords[0][v].x, mesh->mTextureCoords[0][v].y);
      }
      triangles.push_back(t);
    }
  }
  if (triangles.empty()) throw std::runtime_error(path + ": the mesh has no triangles");
  return triangles;
}

}  // namespace vdbappear
