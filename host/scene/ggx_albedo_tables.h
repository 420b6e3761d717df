// The directional albedo tables of single-scattering GGX by which the renderers compensate its energy loss
// (shaders/energy_compensation.h), tabulated in double precision when vkrt is built (albedo_table_entries.h)
// and read by both renderers; and which materials need them.
#pragma once

#include <vector>

#include "scene/scene.h"

namespace vkrt {

// VKRT_GGX_ALBEDO_SIZE^2 entries of E with F = 1, laid out as energy_compensation.h's ggxAlbedo reads them.
const std::vector<float>& ggxAlbedoTable();

// The dielectric's COS x ROUGHNESS x ETA entries of E_eta, reflection and refraction together, laid out as
// ggxDielectricAlbedo reads them.
const std::vector<float>& ggxDielectricAlbedoTable();

// Whether `material` has a GGX lobe that loses energy: a rough one (not a mirror) that reflects (a metal, a
// dielectric with specular reflection) or transmits, or a rough clear coat. Textures only lower the factors
// it reads, so where this is false no point of the material reads the tables.
bool hasRoughSpecular(const Material& material);

// Whether light refracts through a rough lobe of `material` (a rough transmissive volume): the dielectric
// table is read.
bool refractsRoughly(const Material& material);

}  // namespace vkrt
