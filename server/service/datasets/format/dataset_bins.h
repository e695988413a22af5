#pragma once
// What a plan says about its bins and sensors beyond their names: the box and the parts each bin
// is filled with, the camera above it, and the preset (and resolution) each sensor scans with.
// Plans that only name their bins leave these unset; the engine's frame source needs them.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/status.h"
#include "vscan/plan/material_plan.h"

namespace vscan::service::dataset {

// One part type of a bin: a mesh file (read with its unit) or a mesh stored on the server.
struct DatasetPart {
  std::string mesh_file;  // as the plan writes it; relative paths start at the plan's directory
  std::string mesh_id;
  std::string unit = "m";  // of the mesh file: m, cm, mm, in or ft
  double scale = 1.0;
  uint32_t count = 0;
  std::string name;  // default: the file's stem, or the mesh id
  // As a bin plan's parts (docs/BINS.md): a mass, else the density times the enclosed volume; the
  // collision shape "convex_hull" or "convex_decomposition".
  std::optional<double> mass_kg;
  double density_kg_per_m3 = 2700.0;
  std::string collision = "convex_hull";
  // What its instances are made of: none, the default (matte-grey); one, every scene's; several,
  // one chosen per scene (PartMaterialIndex) for all of the part's instances in it.
  std::vector<plan::MaterialPlan> materials;
};

struct DatasetBinFill {
  Eigen::Vector3d inner_size_m = Eigen::Vector3d(0.30, 0.20, 0.15);
  double wall_thickness_m = 0.01;
  std::vector<DatasetPart> parts;
  double max_simulated_s = 30.0;
};

struct DatasetSensor {
  std::string preset;
  // 0: the preset's own; otherwise the image is resampled to this size over the same field of view.
  uint32_t width = 0;
  uint32_t height = 0;
};


inline constexpr uint32_t kMaxPartsInBin = 500;

// Inner sizes within [1 mm, 100 m], walls within (0, 10 m], at least one part, each with a mesh
// (a file or an id, not both), a known unit, a positive scale and count, a known collision shape, at
// most kMaxPartsInBin parts in all; InvalidArgument names the field below `field`, e.g.
// "bins[0].parts[1].count". Masses, densities and the scaled sizes are the fill's own checks
// (physics/fill_checks.h), made once the meshes are read.
Status CheckBinFill(const DatasetBinFill& fill, const std::string& field);
// A preset name and both sizes or neither, each at most 8192.
Status CheckSensor(const DatasetSensor& sensor, const std::string& field);

}  // namespace vscan::service::dataset
