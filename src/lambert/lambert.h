#pragma once
// lambert's front door: the one header a program using the library includes first (docs/api.md).
// It brings the whole public API and nothing else; every header it includes is installed, each
// compiles on its own, and none of them shows the engine's internals (the methods, the solvers,
// the gathers), which are not installed.
//
//   #include "lambert/lambert.h"
//
//   auto scene = lambert::loadScene("cornell", {});                 // a built-in name or a file
//   auto engine = lambert::Radiosity::create(*scene, {});           // the CLI's defaults
//   (*engine)->solve();
//   lambert::writeGlb("out.glb", (*engine)->solution(), {});        // or PNG, EXR, lightmaps, lux
//
// Errors are values (Result<T>, Status), never exceptions, but for one: a long call stops with
// lambert::Cancelled once a program that takes interrupts asks it to (core/cancel.h). All names
// are in namespace lambert.

// Errors, warnings, cancellation, figures and the version.
#include "lambert/core/cancel.h"
#include "lambert/core/error.h"
#include "lambert/core/stats.h"
#include "lambert/core/warning.h"
#include "lambert/version.h"

// Scenes: plain data, the built-in ones, loaded from a file, and their lights.
#include "lambert/light/lights.h"
#include "lambert/load/scene_file.h"
#include "lambert/scene/builtin.h"
#include "lambert/scene/scene.h"

// The engine: its options (plain structs, or by the CLI's names), the solve and its view.
#include "lambert/core/communicator.h"
#include "lambert/method/options.h"
#include "lambert/engine/radiosity.h"
#include "lambert/method/solution.h"
#include "lambert/engine/radiosity_settings.h"

// What a solution gives: images of a view, lightmaps and probes, illuminance in lux.
#include "lambert/bake/lightmaps.h"
#include "lambert/bake/probes.h"
#include "lambert/core/photometric.h"
#include "lambert/design/illuminance.h"
#include "lambert/render/scene_camera.h"
#include "lambert/render/solution_image.h"
#include "lambert/render/tonemap.h"

// Writing it: PNG, EXR, glb with the light baked in, vertex files, lightmapped glb.
#include "lambert/io/exr.h"
#include "lambert/io/gltf_export.h"
#include "lambert/io/lightmap_export.h"
#include "lambert/io/png.h"
#include "lambert/io/vertices.h"
