#pragma once
// Where a picture of a scene is taken from, decided once for every command that draws (render,
// animate, view, reference, compare): the camera asked for, in the scene file's own frame and
// unit; else the camera the scene gives; else one chosen from the geometry.
//
// The chosen camera stands inside a closed scene (a building, a room: its walls face in) and
// outside an open one (a box with an open side, an object). Closed is decided by casting rays
// from a grid of points over the scene's bounds: a point is enclosed when its rays hit the fronts
// of faces all round, at most 5% escaping to infinity (through windows) and 5% meeting the back of
// a one-sided face (a point behind a wall, outside the building or inside a solid). The scene is
// closed when at least 10% of the points are enclosed, so that the inside of a closed two-sided
// object in an open scene does not count (nor does the back of a box open on one side, as the
// Cornell box). Among enclosed points the one
// with the longest mean free path (the largest open space) is taken and raised to 55% of the
// floor-to-ceiling height. Up is the file's up axis, unless the emitters' mean normal points down
// another axis of the file's frame (ceiling lights; MGF files written y-up). Of 64 horizontal directions, the camera looks down the one whose view
// (a 9 × 7 fan of rays over the picture, from the eye set back to 80% of the free distance
// behind it) meets the most front faces, the longest line of sight among views alike. Cost: one
// BVH over the scene and about 8³ × 128 + 64 × 65 rays, milliseconds for 10⁵ faces.
#include <optional>

#include "lambert/core/error.h"
#include "lambert/scene/scene.h"

namespace lambert {

// A camera given in the scene file's own coordinates (Scene::fileFrame: an MGF file's z-up
// metres as written in it, an OBJ's numbers in its unit, a glTF's metres, a scene file's units).
// What is empty comes from the camera the scene would otherwise be seen from; eye and target are
// given together. up defaults to the file's up axis when the eye is given.
struct CameraRequest {
  std::optional<Vec3> eye, target, up;
  std::optional<double> verticalFovDegrees;  // degrees, in (0, 180)
};

// Where the camera came from, for tests and stats.
enum class CameraSource {
  Request,  // eye and target given (CameraRequest)
  Scene,    // the scene's own camera
  Inside,   // default view of a closed scene: the eye is in its largest open space
  Outside,  // default view of an open scene: from in front (−z), 25° above the horizon, 1.5 diagonals away
};
const char* cameraSourceName(CameraSource source);

struct ChosenCamera {
  Camera camera;
  CameraSource source = CameraSource::Outside;
};

// A camera for a scene that gives none, in scene coordinates (see the head of this file).
ChosenCamera defaultCamera(const Scene& scene);

// The camera to draw the scene from: the request over the scene's camera (or defaultCamera when
// the scene gives none). An error, naming the option, for a request that cannot be a camera: an
// eye without a target, the target on the eye, an up that is zero or along the view, a field of
// view outside (0°, 180°), a coordinate that is not finite.
Result<ChosenCamera> sceneCamera(const Scene& scene, const CameraRequest& request);

}  // namespace lambert
