#include "service/bins/bin_scene.h"

#include <cstdio>

#include "geometry/open_bin_mesh.h"

namespace vscan::service {
namespace {

std::string BinMeshName(const physics::BinSpec& bin) {
  char buffer[96];
  std::snprintf(buffer, sizeof(buffer), "bin %gx%gx%g m, walls %g m", bin.inner_size.x(), bin.inner_size.y(),
                bin.inner_size.z(), bin.wall_thickness);
  return buffer;
}

}  // namespace

std::string PartLabel(const std::string& name, size_t instance) { return name + "#" + std::to_string(instance + 1); }

StatusOr<BinPlacement> PlaceBinInScene(scenes::SceneRegistry& registry, const BinFillPlan& plan,
                                       const physics::FillResult& result) {
  const physics::BinSpec& bin = plan.request.bin;
  std::vector<store::ObjectRecord> objects;
  store::ObjectRecord bin_object;
  bin_object.label = plan.request.name.empty() ? "bin" : plan.request.name;
  bin_object.pose = bin.world_from_bin.matrix();
  if (plan.request.mesh_bin) {
    bin_object.mesh_id = plan.request.bin_mesh_id;
    bin_object.scale = plan.request.bin_mesh_scale;
  }  // else mesh_id left empty: the new bin mesh
  objects.push_back(std::move(bin_object));
  for (const physics::PlacedPart& placed : result.parts) {
    store::ObjectRecord part;
    part.mesh_id = plan.request.parts[placed.type].mesh_id;
    part.label = PartLabel(plan.parts[placed.type].name, placed.instance);
    part.pose = placed.world_from_part.matrix();
    part.scale = plan.request.parts[placed.type].scale;
    part.material = plan.request.parts[placed.type].material;
    objects.push_back(std::move(part));
  }
  auto stored = plan.request.mesh_bin
                    ? registry.catalogue().AddObjects(plan.request.scene_id, std::move(objects))
                    : registry.AddObjectsWithMesh(plan.request.scene_id,
                                                          geometry::OpenBinMesh(bin.inner_size, bin.wall_thickness),
                                                          BinMeshName(bin), std::move(objects));
  ASSIGN_OR_RETURN(store::Catalogue::AddedObjects added, std::move(stored));
  BinPlacement placement;
  placement.revision = added.revision;
  placement.bin = std::move(added.objects.front());
  placement.parts.assign(std::make_move_iterator(added.objects.begin() + 1),
                         std::make_move_iterator(added.objects.end()));
  return placement;
}

}  // namespace vscan::service
