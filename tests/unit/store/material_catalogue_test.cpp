// Materials in the catalogue: a mesh's default and an object's override are stored as given,
// survive a reopen, and a row that is neither a preset nor four values reads as DATA_LOSS.

#include <gtest/gtest.h>
#include <sqlite3.h>

#include "store/catalogue.h"
#include "vscan_test/temp_dir.h"
#include "sqlite_query.h"

namespace vscan::store {
namespace {

MeshRecord MaterialTestMesh(std::optional<MaterialRecord> material) {
  MeshRecord mesh;
  mesh.name = "cube";
  mesh.sha256 = std::string(64, 'c');
  mesh.vertex_count = 8;
  mesh.triangle_count = 12;
  mesh.bounds_min = {-0.05, -0.05, -0.05};
  mesh.bounds_max = {0.05, 0.05, 0.05};
  mesh.source_unit = LengthUnit::kMetre;
  mesh.material = std::move(material);
  return mesh;
}

MaterialRecord MaterialPresetRecord(const std::string& name) {
  MaterialRecord material;
  material.preset = name;
  return material;
}

MaterialRecord MaterialValuesRecord(double albedo, double metallic, double roughness, double specular) {
  return MaterialRecord{"", albedo, metallic, roughness, specular};
}

class MaterialCatalogueTest : public ::testing::Test {
 protected:
  std::filesystem::path db_path() const { return dir_.path() / "catalogue.sqlite"; }
  test::TempDir dir_;
};

TEST_F(MaterialCatalogueTest, MeshAndObjectMaterialsSurviveAReopen) {
  std::string preset_mesh, values_mesh, bare_mesh, scene_id, with_override, without_override;
  // Values that a decimal round trip would not keep exactly.
  const MaterialRecord odd = MaterialValuesRecord(0.1 + 0.2, 1.0 / 3.0, 0.02, 0.04);
  {
    auto catalogue = Catalogue::Open(db_path());
    ASSERT_TRUE(catalogue.ok()) << catalogue.status().ToString();
    auto a = (*catalogue)->InsertMesh(MaterialTestMesh(MaterialPresetRecord("machined-aluminium")));
    auto b = (*catalogue)->InsertMesh(MaterialTestMesh(odd));
    auto c = (*catalogue)->InsertMesh(MaterialTestMesh(std::nullopt));
    ASSERT_TRUE(a.ok() && b.ok() && c.ok());
    preset_mesh = a->mesh_id;
    values_mesh = b->mesh_id;
    bare_mesh = c->mesh_id;
    auto scene = (*catalogue)->CreateScene("materials");
    ASSERT_TRUE(scene.ok());
    scene_id = scene->scene_id;
    ObjectRecord object;
    object.scene_id = scene_id;
    object.mesh_id = preset_mesh;
    object.material = MaterialPresetRecord("black-abs");
    auto first = (*catalogue)->AddObject(object);
    ASSERT_TRUE(first.ok()) << first.status().ToString();
    EXPECT_EQ(first->first.material, MaterialPresetRecord("black-abs"));
    with_override = first->first.object_id;
    object.material.reset();
    object.mesh_id = bare_mesh;
    auto second = (*catalogue)->AddObject(object);
    ASSERT_TRUE(second.ok());
    without_override = second->first.object_id;
  }
  auto catalogue = Catalogue::Open(db_path());
  ASSERT_TRUE(catalogue.ok());
  EXPECT_EQ((*catalogue)->GetMesh(preset_mesh)->material, MaterialPresetRecord("machined-aluminium"));
  EXPECT_EQ((*catalogue)->GetMesh(values_mesh)->material, odd);
  EXPECT_FALSE((*catalogue)->GetMesh(bare_mesh)->material.has_value());
  auto listed = (*catalogue)->ListMeshes("", 10);
  ASSERT_TRUE(listed.ok());
  ASSERT_EQ(listed->size(), 3u);
  auto scene = (*catalogue)->GetScene(scene_id);
  ASSERT_TRUE(scene.ok());
  ASSERT_EQ(scene->objects.size(), 2u);
  EXPECT_EQ(scene->objects[0].object_id, with_override);
  EXPECT_EQ(scene->objects[0].material, MaterialPresetRecord("black-abs"));
  EXPECT_EQ(scene->objects[1].object_id, without_override);
  EXPECT_FALSE(scene->objects[1].material.has_value());
  // A preset stores its name alone; values store no name.
  EXPECT_EQ(test::QueryInt(db_path(), "SELECT count(*) FROM meshes WHERE material_preset IS NOT NULL AND "
                                      "material_albedo IS NULL AND material_specular IS NULL"), 1);
  EXPECT_EQ(test::QueryInt(db_path(), "SELECT count(*) FROM meshes WHERE material_preset IS NULL AND "
                                      "material_roughness = 0.02"), 1);
}

TEST_F(MaterialCatalogueTest, SetObjectMaterialSetsReplacesAndClearsWithANewRevision) {
  auto catalogue = Catalogue::Open(db_path());
  ASSERT_TRUE(catalogue.ok());
  auto mesh = (*catalogue)->InsertMesh(MaterialTestMesh(MaterialPresetRecord("cardboard")));
  auto scene = (*catalogue)->CreateScene("s");
  ASSERT_TRUE(mesh.ok() && scene.ok());
  ObjectRecord object;
  object.scene_id = scene->scene_id;
  object.mesh_id = mesh->mesh_id;
  object.label = "kept";
  auto added = (*catalogue)->AddObject(object);
  ASSERT_TRUE(added.ok());
  const std::string id = added->first.object_id;

  auto set = (*catalogue)->SetObjectMaterial(scene->scene_id, id, MaterialValuesRecord(0.2, 0.0, 0.7, 0.05));
  ASSERT_TRUE(set.ok()) << set.status().ToString();
  EXPECT_EQ(set->second, added->second + 1);
  EXPECT_EQ(set->first.label, "kept");
  EXPECT_EQ(set->first.material, MaterialValuesRecord(0.2, 0.0, 0.7, 0.05));
  EXPECT_EQ((*catalogue)->GetScene(scene->scene_id)->objects[0].material, MaterialValuesRecord(0.2, 0.0, 0.7, 0.05));

  auto replaced = (*catalogue)->SetObjectMaterial(scene->scene_id, id, MaterialPresetRecord("white-abs"));
  ASSERT_TRUE(replaced.ok());
  EXPECT_EQ((*catalogue)->GetScene(scene->scene_id)->objects[0].material, MaterialPresetRecord("white-abs"));
  EXPECT_EQ(test::QueryInt(db_path(), "SELECT count(*) FROM objects WHERE material_albedo IS NULL"), 1);

  auto cleared = (*catalogue)->SetObjectMaterial(scene->scene_id, id, std::nullopt);
  ASSERT_TRUE(cleared.ok());
  EXPECT_EQ(cleared->second, added->second + 3);
  EXPECT_FALSE((*catalogue)->GetScene(scene->scene_id)->objects[0].material.has_value());
  // The mesh's default is untouched by an object's override.
  EXPECT_EQ((*catalogue)->GetMesh(mesh->mesh_id)->material, MaterialPresetRecord("cardboard"));

  const auto missing = (*catalogue)->SetObjectMaterial(scene->scene_id, "obj_0000000000000000", std::nullopt);
  EXPECT_EQ(missing.status().code(), StatusCode::kNotFound);
  EXPECT_NE(missing.status().message().find("object_id"), std::string::npos);
  // A refused call changes nothing, revision included.
  EXPECT_EQ((*catalogue)->GetScene(scene->scene_id)->revision, cleared->second);
  EXPECT_EQ((*catalogue)->SetObjectMaterial("scn_0000000000000000", id, std::nullopt).status().code(),
            StatusCode::kNotFound);
}

TEST_F(MaterialCatalogueTest, AHalfWrittenMaterialRowIsDataLoss) {
  std::string mesh_id;
  {
    auto catalogue = Catalogue::Open(db_path());
    ASSERT_TRUE(catalogue.ok());
    auto mesh = (*catalogue)->InsertMesh(MaterialTestMesh(std::nullopt));
    ASSERT_TRUE(mesh.ok());
    mesh_id = mesh->mesh_id;
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(db_path().c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "UPDATE meshes SET material_albedo = 0.5", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
  auto catalogue = Catalogue::Open(db_path());
  ASSERT_TRUE(catalogue.ok());
  const Status status = (*catalogue)->GetMesh(mesh_id).status();
  EXPECT_EQ(status.code(), StatusCode::kDataLoss);
  EXPECT_NE(status.message().find(mesh_id), std::string::npos) << status.message();
}

}  // namespace
}  // namespace vscan::store
