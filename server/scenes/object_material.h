#pragma once
// The material a scan sees on a placed object: the object's override, else its mesh's default,
// else the engine's default (the first preset, matte-grey).

#include "sensor/material.h"
#include "store/catalogue.h"
#include "vscan/common/status.h"

namespace vscan::scenes {

// The values a stored material stands for: its preset's, or its own. DATA_LOSS for a preset this
// server does not know (the service refuses unknown presets, so only a foreign database has one).
StatusOr<sensor::Material> MaterialOf(const store::MaterialRecord& record);

// object.material > mesh.material > sensor::DefaultMaterial().
StatusOr<sensor::Material> EffectiveMaterial(const store::ObjectRecord& object, const store::MeshRecord& mesh);

}  // namespace vscan::scenes
