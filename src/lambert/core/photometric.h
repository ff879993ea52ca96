#pragma once
// Photometric units from lambert's radiometric RGB. lambert transports light as RGB radiometric
// quantities (W/m², W/sr); a lighting designer reads lux and candela. The conversion is the one
// glTF (KHR_lights_punctual) and Blender use: 683 lm/W, applied to the Rec. 709 luminance of the
// RGB value (0.2126 R + 0.7152 G + 0.0722 B, Rgb::luminance), so that a white light of I cd is
// I/683 W/sr in each channel and its illuminance in lux is 683 × the luminance of its irradiance.
#include "lambert/core/rgb.h"

namespace lambert {

// Candela → W/sr and lux → W/m² (and back): the luminous efficacy glTF and Blender convert with.
inline constexpr double kLumensPerWatt = 683;

// Illuminance in lux of an RGB irradiance E in W/m².
constexpr double illuminanceLux(const Rgb& irradiance) { return kLumensPerWatt * irradiance.luminance(); }
// Luminance in cd/m² of an RGB radiance L in W/(m²·sr).
constexpr double luminanceCandelasPerSquareMetre(const Rgb& radiance) { return kLumensPerWatt * radiance.luminance(); }

}  // namespace lambert
