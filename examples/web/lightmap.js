// Shows lambert's lightmapped glb (`lambert solve --lightmaps --export OUT.glb`, docs/lightmaps.md)
// in three.js from the glb's own camera, drawn as lambert's `--image` draws it, so that the two
// pictures can be compared pixel by pixel (tests/real_clients_test.cpp).
//
// URL parameters:
//   glb=URL        the glb (relative to this page), required
//   exposure=S     stops: radiance × 2^S before the sRGB transfer, as lambert's images (default 0)
//   material=M     lambert (default): each material as MeshLambertMaterial, whose lightmap term is
//                  exactly ρ/π · E; standard: GLTFLoader's MeshStandardMaterial as loaded, whose
//                  specular layer (glTF's 4% dielectric lobe, even at roughness 1) takes its share
//                  of the lightmap's light from the diffuse (1 − E_spec, 5–10%), and returns none
//                  of it where there is no environment map
//   lightmap=L     glb (default): the glb's RGBM lightmaps (LAMBERT_lightmap, decoded by the plugin
//                  lambert-lightmap.js); exr: the HDR OUT-lightmap-K.exr beside the glb (three's
//                  EXRLoader); none: no lightmap
//   antialias=0|1  multisampling (default 1)
//   width=W, height=H  the canvas's size in pixels (default: the window's)
// The page logs "lambert-lightmap: rendered ..." or "lambert-lightmap: error ..." to the console.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { EXRLoader } from 'three/addons/loaders/EXRLoader.js';
import { LambertLightmapPlugin, decodeLambertLightmap } from './lambert-lightmap.js';

const params = new URLSearchParams(location.search);
const glbUrl = params.get('glb');
const exposureStops = Number(params.get('exposure') ?? 0);
const materialKind = params.get('material') ?? 'lambert';
const lightmapSource = params.get('lightmap') ?? 'glb';
const antialias = (params.get('antialias') ?? '1') !== '0';

function fail(message) {
  document.getElementById('status').textContent = message;
  console.error(`lambert-lightmap: error: ${message}`);
  document.title = 'error';
}

// lightmap=exr: each lightMap replaced by its atlas's HDR original beside the glb, E itself (so
// intensity 1), read with three's own filtering.
async function useExrLightmaps(scene) {
  const atlases = new Map();  // GLTFLoader names a texture after its image: "<stem>-lightmap-K"
  const materials = [];
  scene.traverse((object) => { if (object.isMesh && object.material.lightMap) materials.push(object.material); });
  for (const material of materials) {
    const name = material.lightMap.name;
    if (!atlases.has(name)) {
      const texture = await new EXRLoader().setDataType(THREE.HalfFloatType).loadAsync(new URL(`${name}.exr`, new URL(glbUrl, location.href)).href);
      // EXRLoader stores the file's last row first (OpenGL's v = 0 at the bottom); glTF's (0, 0)
      // is the atlas's top-left corner: put the rows back in the file's order.
      const { data, height } = texture.image;
      const row = data.length / height, rows = data.slice();
      for (let y = 0; y < height; ++y) data.set(rows.subarray((height - 1 - y) * row, (height - y) * row), y * row);
      texture.flipY = false;
      texture.minFilter = THREE.LinearFilter;  // no mip-maps: they would mix charts across their padding
      texture.magFilter = THREE.LinearFilter;
      texture.generateMipmaps = false;
      texture.channel = material.lightMap.channel;
      texture.needsUpdate = true;
      atlases.set(name, texture);
    }
    material.lightMap = atlases.get(name);
    material.lightMapIntensity = 1;
    material.needsUpdate = true;
  }
}

// The glTF material as MeshLambertMaterial: the same base colour, textures, emission and
// lightmap, without the specular layer lambert's diffuse surfaces do not have.
function asLambert(material) {
  return new THREE.MeshLambertMaterial({
    name: material.name,
    color: material.color, map: material.map,
    emissive: material.emissive, emissiveMap: material.emissiveMap, emissiveIntensity: material.emissiveIntensity,
    lightMap: material.lightMap, lightMapIntensity: material.lightMapIntensity,
    side: material.side, transparent: material.transparent, opacity: material.opacity,
  });
}

async function main() {
  if (!glbUrl) return fail('no glb: open lightmap.html?glb=URL');
  const width = Number(params.get('width') ?? window.innerWidth), height = Number(params.get('height') ?? window.innerHeight);
  if (!(width > 0 && height > 0)) return fail(`no size: ${width}x${height}`);
  const renderer = new THREE.WebGLRenderer({ antialias, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height);
  // lambert's tone mapping (render/tonemap.h): radiance × 2^stops, clamped, sRGB, 8 bits.
  renderer.toneMapping = THREE.LinearToneMapping;
  renderer.toneMappingExposure = 2 ** exposureStops;
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  renderer.setClearColor(0x000000, 1);
  document.body.appendChild(renderer.domElement);

  const loader = new GLTFLoader().register((parser) => new LambertLightmapPlugin(parser));
  const gltf = await loader.loadAsync(glbUrl);
  // No lights and no environment: the light is all in the lightmaps.
  const scene = gltf.scene;
  if (materialKind === 'lambert') {
    scene.traverse((object) => {
      if (object.isMesh) {
        object.material = asLambert(object.material);
        decodeLambertLightmap(object.material);
      }
    });
  } else if (materialKind !== 'standard') {
    return fail(`material=${materialKind}: lambert or standard`);
  }
  if (lightmapSource === 'exr') {
    await useExrLightmaps(scene);
  } else if (lightmapSource === 'none') {
    scene.traverse((object) => { if (object.isMesh) object.material.lightMap = null; });
  } else if (lightmapSource !== 'glb') {
    return fail(`lightmap=${lightmapSource}: glb, exr or none`);
  }
  if (gltf.cameras.length === 0) return fail('the glb has no camera');
  const camera = gltf.cameras[0];
  camera.aspect = width / height;  // the glb's yfov is vertical, as lambert's camera's
  camera.updateProjectionMatrix();
  renderer.render(scene, camera);
  let lightmaps = 0;
  scene.traverse((object) => { if (object.isMesh && object.material.lightMap) ++lightmaps; });
  document.title = 'rendered';
  console.log(`lambert-lightmap: rendered ${width}x${height}, ${lightmaps} lightmapped meshes, material ${materialKind}, ` +
              `lightmap ${lightmapSource}, exposure ${exposureStops}, three r${THREE.REVISION}`);
}

main().catch((error) => fail(error?.stack ?? String(error)));
