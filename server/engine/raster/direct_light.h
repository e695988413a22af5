#pragma once
// The returned light's direct term as the raster shaders evaluate it per pixel: the sensor's own
// emitter and each object's material (docs/SENSORS.md, "The returned signal").

#include <span>

#include "sensor/material.h"
#include "sensor/returned_signal.h"

namespace vscan::raster {

struct DirectLight {
  sensor::Emitter emitter;  // in the sensor frame
  // materials[id] is the material of the object with instance id `id`; ids past the end (and 0)
  // take default_material, as capture::ReturnedSignals does. Must outlive the scan.
  std::span<const sensor::Material> materials;
  sensor::Material default_material;
};

// The material DirectLight gives the object with this instance id.
inline const sensor::Material& MaterialOf(const DirectLight& light, uint32_t instance_id) {
  return instance_id != 0 && instance_id < light.materials.size() ? light.materials[instance_id]
                                                                  : light.default_material;
}

}  // namespace vscan::raster
