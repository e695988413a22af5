#include "service/datasets/format/dataset_materials.h"

#include "service/job/json_writer.h"

namespace vscan::service::dataset {
namespace {

uint64_t Mix(uint64_t x, uint64_t more) {
  x += 0x9e3779b97f4a7c15ull + more;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Keeps the material draws apart from the fill's and the views' draws of the same seed.
constexpr uint64_t kMaterialStream = 0x6d6174657269616cull;  // "material"

}  // namespace

size_t PartMaterialIndex(uint64_t seed, size_t bin_index, size_t part_index, size_t count) {
  if (count <= 1) return 0;
  const uint64_t draw = Mix(Mix(Mix(seed, kMaterialStream), bin_index), part_index);
  // count is small (kMaxMaterialChoices): the modulo bias is below 2^-57.
  return static_cast<size_t>(draw % count);
}

void WriteMaterial(JsonWriter& json, const plan::MaterialPlan& material) {
  json.Open('{');
  if (!material.preset.empty()) {
    json.Key("preset").Value(material.preset);
  } else {
    json.Key("diffuse_albedo").Value(material.diffuse_albedo);
    json.Key("metallic").Value(material.metallic);
    json.Key("roughness").Value(material.roughness);
    json.Key("specular_reflectance").Value(material.specular_reflectance);
  }
  json.Close('}');
}

std::string SceneMaterialsJson(const std::vector<InstanceMaterial>& instances) {
  JsonWriter json;
  json.Open('{');
  json.Key("instances").Open('[');
  for (const InstanceMaterial& instance : instances) {
    json.Open('{');
    json.Key("instance_id").Value(uint64_t{instance.instance_id});
    json.Key("obj_id").Value(uint64_t{instance.obj_id});
    json.Key("part").Value(instance.part);
    json.Key("material");
    WriteMaterial(json, instance.material);
    json.Close('}');
  }
  json.Close(']');
  json.Close('}');
  return json.str() + "\n";
}

}  // namespace vscan::service::dataset
