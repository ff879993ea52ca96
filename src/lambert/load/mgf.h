#pragma once
// MGF, the Materials and Geometry Format (Greg Ward, LBL, 1994–96), read by our own parser from
// the published specification. What is read:
//   # comments, '\' line continuation (the newline counts as a space);
//   vertices: v name =, v name = template, v name (make current), with p x y z and n dx dy dz
//     (a normal only orients ring and torus; lambert shades from its own mesh);
//   f v1 v2 v3 ... (counter-clockwise seen from the front, the right-hand rule, as lambert's);
//   materials: m name =, m name = template, m name, bare m (the unnamed default, reset to
//     defaults: rd 0, ed 0, 2 sides); rd ρ (photometric diffuse reflectance, [0, 1]) and ed ε
//     (diffuse emittance, lm/m²), each taking the current colour's chromaticity; sides 1|2
//     (Material::twoSided; MGF's default is 2);
//   colours: c name =, c name = template, c name, bare c (the unnamed default: equal-energy
//     white, reset); cxy x y; cspec λmin λmax v1 ... (nm, evenly spaced; samples may be negative,
//     as the CIE daylight basis functions of MGF's standard illuminant library are); cct T (K,
//     Planck); cmix w1 c1 w2 c2 ... (weights of relative photometric brightness, as the spec
//     says: a sum in CIE XYZ of each colour at unit luminance, which is exact for spectra too;
//     weights may be negative). A colour is what it integrates to; one that is no real colour
//     (a negative X, Y or Z, or no luminance: cxy 0.4 0, a basis function alone) is repaired
//     where a material uses it with a nonzero rd or ed, with a warning naming the line that set
//     it: negative components clipped to 0; no luminance left: moved toward white onto the
//     boundary of real chromaticities (the spectral locus and the purple line), the most
//     saturated real colour of its hue; nothing left: white;
//   transforms: xf with -t dx dy dz, -rx/-ry/-rz degrees (counter-clockwise looking down the axis
//     toward the origin), -s f, -mx/-my/-mz, -i N (the following arguments N times) and -a N
//     (N instances of the enclosed entities, the arguments after -a applied 0, 1, ..., N−1 times;
//     several -a make a grid); each argument acts on the result of the ones before it, and an
//     inner xf acts before its enclosing ones; bare xf ends the context (balanced per file);
//   i file [xf args]: includes, relative to the including file wherever that leads (RenderPark's
//     hospital includes ../Materials/), at most 32 deep, no cycles; MgfOptions::includeRoot, when
//     given, confines them to a folder (for a service reading files it did not choose;
//     load/mgf_source.h);
//   o name ... o: objects, named "outer/inner", each a set of smooth regions (scene/regions.h);
//   sph, cyl, cone, ring, torus, prism, tessellated with MgfOptions::divisions segments per full
//     circle (a sphere: that many around, half as many pole to pole). Normals face outward; a
//     negative radius (both radii of a cone or torus) turns them inward; a ring faces along its
//     centre vertex's normal; a prism is extruded away from its face's normal (all faces out), or
//     toward it when the length is negative (all in).
//   ies file [-m multiplier] [transform]: an IES (or EULUMDAT .ldt) luminaire, relative to the
//     including file, as a LightKind::Luminaire at the origin of its frame, aimed down its −z,
//     its C = 0 plane along its x (MGF's notes on IES files), candela × multiplier, white.
// What is ignored: td, rs, ts, ir (one warning per kind: lambert is diffuse-only and opaque); fh
//   (one warning: unsupported); unknown entities (one warning per kind, file:line).
// What is repaired, with a warning naming file:line: rd above 1 (lowered below 1, as RenderPark
//   does); a colour that is no real colour (above); an o or xf end with nothing to end (ignored);
//   an o name of several words (joined);
//   an xf (or xf -a array) left open at the end of its file (ended there); a sph, cyl, cone, ring, torus or prism
//   with no area (zero radii, coincident ends, zero length: skipped); ring or torus radii given
//   in the wrong order (swapped).
// Units: MGF is in metres (the spec's default coordinate system), so metresPerUnit = 1; a file
//   in other units scales itself with xf -s. MGF scenes are z-up (Radiance's and the IES
//   luminaire notes' convention), lambert's are y-up: every point (x, y, z) becomes (x, z, −y),
//   a rotation (no mirroring).
// Colour: an MGF colour is a chromaticity; ρ's luminance is rd. CIE XYZ at unit luminance → linear
//   Rec. 709 primaries (the sRGB matrix), then each channel divided by that of MGF's
//   equal-energy white (x = y = 1/3), so white maps to RGB (1, 1, 1) (a von Kries scaling in the
//   RGB space, from E instead of D65), negative channels (out of gamut) clipped to 0 and the
//   result scaled back to Rec. 709 luminance 1. ρ = rd × that; ρ of 1 or more in a channel is
//   lowered (boundedAlbedo). cspec and cct integrate against the CIE 1931 2° colour matching
//   functions in the multi-lobe Gaussian fit of Wyman, Sloan and Shirley 2013 (JCGT 2(2));
//   core/cie_colour.h.
// Emission: ed is a luminous emittance M_v in lm/m² from a Lambertian emitter, so its luminance
//   is M_v/π cd/m²; lambert's L_e in W/(m²·sr) is that divided by 683 lm/W (kLumensPerWatt, the
//   efficacy the glTF reader converts with, so that the same lamp reads the same from either
//   format): L_e = ed/(π·683) × the colour's RGB at unit luminance.
// Errors (Error{"file:line: what, how to proceed"}), for what cannot be understood: an undefined
// vertex, material or colour; wrong number or type of arguments; a non-finite number; negative
// rd or ed (a sign cannot be guessed); a cone or torus whose radii differ in sign; a ring or
// torus without a normal; a missing include ("cannot open include 'x.mgf'"), an include cycle,
// nesting over 32, an include outside MgfOptions::includeRoot; no faces at all.
#include <string>

#include "lambert/core/error.h"
#include "lambert/scene/regions.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct MgfOptions {
  int divisions = 16;  // segments per full circle of sph, cyl, cone, ring, torus (at least 3)
  RegionOptions regions;
  // Includes must resolve (symbolic links followed) inside this folder; empty: wherever they lead.
  std::string includeRoot;
};

// The scene is named after the file, lit by its emissive materials; it gives no camera
// (cameraGiven is false: render/scene_camera.h chooses the view).
// Warnings (ignored entities, dropped faces, clamped albedo) go through warning().
Result<Scene> readMgf(const std::string& path, const MgfOptions& options = {});

}  // namespace lambert
