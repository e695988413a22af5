// The material a scan sees on an object: its override, else its mesh's default, else the engine's
// default; and the scene the registry builds carries it on every instance.

#include "scenes/object_material.h"

#include <gtest/gtest.h>

#include "scenes/scene_registry.h"
#include "sensor/material.h"
#include "store/blob_store.h"
#include "vscan_test/temp_dir.h"

namespace vscan::scenes {
namespace {

store::MaterialRecord NamedMaterial(const std::string& name) {
  store::MaterialRecord record;
  record.preset = name;
  return record;
}

void ExpectSameMaterial(const sensor::Material& a, const sensor::Material& b) {
  EXPECT_EQ(a.albedo, b.albedo);
  EXPECT_EQ(a.metallic, b.metallic);
  EXPECT_EQ(a.roughness, b.roughness);
  EXPECT_EQ(a.specular_reflectance, b.specular_reflectance);
}

TEST(ObjectMaterialTest, OverrideBeatsMeshDefaultWhichBeatsTheEngineDefault) {
  store::MeshRecord mesh;
  store::ObjectRecord object;
  auto none = EffectiveMaterial(object, mesh);
  ASSERT_TRUE(none.ok());
  // matte-grey, written out: a change to the default shows here.
  ExpectSameMaterial(*none, sensor::Material{0.5, 0.0, 0.9, 0.04});
  ExpectSameMaterial(*none, sensor::DefaultMaterial());

  mesh.material = NamedMaterial("machined-aluminium");
  auto from_mesh = EffectiveMaterial(object, mesh);
  ASSERT_TRUE(from_mesh.ok());
  ExpectSameMaterial(*from_mesh, sensor::Material{0.87, 1.0, 0.3, 0.04});

  object.material = store::MaterialRecord{"", 0.25, 0.5, 0.75, 0.125};
  auto from_object = EffectiveMaterial(object, mesh);
  ASSERT_TRUE(from_object.ok());
  ExpectSameMaterial(*from_object, sensor::Material{0.25, 0.5, 0.75, 0.125});

  mesh.material.reset();
  object.material = NamedMaterial("black-abs");
  auto override_only = EffectiveMaterial(object, mesh);
  ASSERT_TRUE(override_only.ok());
  ExpectSameMaterial(*override_only, sensor::Material{0.04, 0.0, 0.4, 0.045});
}

TEST(ObjectMaterialTest, AStoredPresetThisServerDoesNotKnowIsDataLoss) {
  store::MeshRecord mesh;
  mesh.material = NamedMaterial("unobtainium");
  const auto resolved = EffectiveMaterial(store::ObjectRecord{}, mesh);
  EXPECT_EQ(resolved.status().code(), StatusCode::kDataLoss);
  EXPECT_NE(resolved.status().message().find("unobtainium"), std::string::npos);
  // An object's valid override does not read the mesh's.
  store::ObjectRecord object;
  object.material = NamedMaterial("cardboard");
  EXPECT_TRUE(EffectiveMaterial(object, mesh).ok());
}

constexpr std::string_view kTriangleObj = "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nf 1 2 3\n";

TEST(ObjectMaterialTest, PreparedScansCarryEachObjectsEffectiveMaterial) {
  test::TempDir dir;
  auto catalogue = store::Catalogue::Open(dir.path() / "catalogue.sqlite");
  ASSERT_TRUE(catalogue.ok());
  store::BlobStore blobs(dir.path() / "blobs");
  ASSERT_TRUE(blobs.Open().ok());
  SceneRegistry registry(**catalogue, blobs);

  MeshUpload upload;
  upload.name = "tri.obj";
  upload.format = geometry::MeshFileFormat::kObj;
  upload.unit = store::LengthUnit::kMetre;
  upload.material = NamedMaterial("polished-steel");
  auto steel = registry.AddMesh(kTriangleObj, upload);
  ASSERT_TRUE(steel.ok()) << steel.status().ToString();
  EXPECT_EQ(steel->material, NamedMaterial("polished-steel"));
  upload.material.reset();
  auto bare = registry.AddMesh(kTriangleObj, upload);
  ASSERT_TRUE(bare.ok());

  auto scene = (*catalogue)->CreateScene("s");
  ASSERT_TRUE(scene.ok());
  store::ObjectRecord object;
  object.scene_id = scene->scene_id;
  object.mesh_id = steel->mesh_id;
  ASSERT_TRUE((*catalogue)->AddObject(object).ok());  // the mesh's steel
  object.material = NamedMaterial("white-abs");
  ASSERT_TRUE((*catalogue)->AddObject(object).ok());  // overridden
  object.material.reset();
  object.mesh_id = bare->mesh_id;
  auto last = (*catalogue)->AddObject(object);  // nothing set
  ASSERT_TRUE(last.ok());

  auto target = registry.PrepareScan(scene->scene_id, std::nullopt);
  ASSERT_TRUE(target.ok()) << target.status().ToString();
  ASSERT_EQ(target->instances->size(), 3u);
  ExpectSameMaterial((*target->instances)[0].material, sensor::FindMaterialPreset("polished-steel")->material);
  ExpectSameMaterial((*target->instances)[1].material, sensor::FindMaterialPreset("white-abs")->material);
  ExpectSameMaterial((*target->instances)[2].material, sensor::DefaultMaterial());

  // A new override is a new revision, so the next scan sees it rather than the cached scene.
  ASSERT_TRUE((*catalogue)
                  ->SetObjectMaterial(scene->scene_id, last->first.object_id, NamedMaterial("cardboard"))
                  .ok());
  auto again = registry.PrepareScan(scene->scene_id, std::nullopt);
  ASSERT_TRUE(again.ok());
  ExpectSameMaterial((*again->instances)[2].material, sensor::FindMaterialPreset("cardboard")->material);
}

}  // namespace
}  // namespace vscan::scenes
