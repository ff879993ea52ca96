// lambert's lightmaps in three.js: a GLTFLoader plugin for the glb of `lambert solve --lightmaps
// --export OUT.glb` (docs/lightmaps.md "Output").
//
//   import { LambertLightmapPlugin } from './lambert-lightmap.js';
//   const loader = new GLTFLoader().register((parser) => new LambertLightmapPlugin(parser));
//   const gltf = await loader.loadAsync('OUT.glb');   // no lights, no environment: the light is baked
//
// Each material's LAMBERT_lightmap extension names its atlas, {index, texCoord, encoding: "RGBM",
// range}: the irradiance E in W/m² of a texel is range · (rgb / 255) · (a / 255). The plugin lays
// the atlas on as the material's lightMap (through TEXCOORD_1, three's 'uv1') and patches the
// material's shader so that the lightmap is read as E: the four texels around the point decoded,
// then filtered bilinearly, clamped to the atlas's edge (as lambert's own `--image` reads it;
// filtering the bytes first would multiply two interpolated factors, up to 7% off at a shadow's
// edge). three.js then draws L = ρ/π · E, the radiance lambert computed; set the renderer's
// exposure and sRGB output as lambert's images are (examples/web/lightmap.js).
//
// The older MOZ_lightmap extension (linear 8 bits, E = intensity · rgb / 255; lambert wrote it
// before RGBM) is read too. A material whose type has no lightMap (ShaderMaterial) is left as is.
import * as THREE from 'three';

// The bilinear filter of decoded RGBM texels: `texture2D(lightMap, uv)` in three's lightmap code
// becomes this. textureSize/texelFetch are GLSL ES 3.00, which three.js r163+ always compiles to.
const rgbmFilter = /* glsl */ `
uniform float lambertLightmapRange;
vec4 lambertLightmapTexel( vec2 uv ) {
	ivec2 size = textureSize( lightMap, 0 );
	vec2 p = uv * vec2( size ) - 0.5;
	vec2 f = p - floor( p );
	ivec2 lo = clamp( ivec2( floor( p ) ), ivec2( 0 ), size - 1 );
	ivec2 hi = clamp( ivec2( floor( p ) ) + 1, ivec2( 0 ), size - 1 );
	vec4 t00 = texelFetch( lightMap, ivec2( lo.x, lo.y ), 0 ), t10 = texelFetch( lightMap, ivec2( hi.x, lo.y ), 0 );
	vec4 t01 = texelFetch( lightMap, ivec2( lo.x, hi.y ), 0 ), t11 = texelFetch( lightMap, ivec2( hi.x, hi.y ), 0 );
	vec3 e = mix( mix( t00.rgb * t00.a, t10.rgb * t10.a, f.x ), mix( t01.rgb * t01.a, t11.rgb * t11.a, f.x ), f.y );
	return vec4( e * lambertLightmapRange, 1.0 );
}
`;
const lightmapRead = 'texture2D( lightMap, vLightMapUv )';

// Makes `material` read its lightMap as lambert's RGBM wherever that texture is one the plugin
// marked (its range in userData.lambertRgbmRange), and as three reads any other lightMap: so a
// page may swap the lightMap afterwards. Idempotent; call it again on a material made from
// another (as a page that swaps GLTFLoader's MeshStandardMaterial for MeshLambertMaterial does).
export function decodeLambertLightmap(material) {
  if (material.userData.lambertLightmap) return;
  material.userData.lambertLightmap = true;
  const range = () => material.lightMap?.userData?.lambertRgbmRange;
  material.onBeforeCompile = (shader) => {
    if (range() === undefined) return;
    shader.uniforms.lambertLightmapRange = { get value() { return range(); } };
    // The lightmap is read in lights_fragment_maps (lit materials) or in the material's own
    // fragment code (MeshBasicMaterial): expand the chunk, then replace every read.
    const fragment = shader.fragmentShader.replace('#include <lights_fragment_maps>', THREE.ShaderChunk.lights_fragment_maps);
    if (!fragment.includes(lightmapRead) || !fragment.includes('#include <lightmap_pars_fragment>'))
      throw new Error(`lambert-lightmap: three.js r${THREE.REVISION}'s ${material.type} does not read its lightMap as r187 does`);
    shader.fragmentShader = fragment.replaceAll(lightmapRead, 'lambertLightmapTexel( vLightMapUv )')
      .replace('#include <lightmap_pars_fragment>', `#include <lightmap_pars_fragment>\n#ifdef USE_LIGHTMAP\n${rgbmFilter}\n#endif`);
  };
  material.customProgramCacheKey = () => (range() === undefined ? '' : 'lambert-rgbm-lightmap');
  material.needsUpdate = true;
}

export class LambertLightmapPlugin {
  constructor(parser) {
    this.parser = parser;
    this.name = 'LAMBERT_lightmap';
  }

  async extendMaterialParams(materialIndex, materialParams) {
    const extensions = this.parser.json.materials[materialIndex].extensions ?? {};
    const lambert = extensions.LAMBERT_lightmap, moz = extensions.MOZ_lightmap;
    if (lambert) {
      if (lambert.encoding !== 'RGBM') throw new Error(`LAMBERT_lightmap: encoding ${lambert.encoding} (this plugin reads RGBM)`);
      // GLTFLoader's textures are linear unless a colour map's; their rows are glTF's (flipY false).
      const texture = await this.parser.getDependency('texture', lambert.index);
      texture.channel = lambert.texCoord ?? 1;
      texture.minFilter = THREE.NearestFilter;  // the shader filters the decoded texels itself
      texture.magFilter = THREE.NearestFilter;
      texture.generateMipmaps = false;
      texture.userData.lambertRgbmRange = lambert.range;
      texture.needsUpdate = true;
      materialParams.lightMap = texture;
      materialParams.lightMapIntensity = 1;
    } else if (moz) {
      const texture = await this.parser.getDependency('texture', moz.index);
      texture.channel = moz.texCoord ?? 1;
      materialParams.lightMap = texture;
      materialParams.lightMapIntensity = moz.intensity ?? 1;
    }
  }

  afterRoot(result) {
    result.scene.traverse((object) => {
      if (!object.isMesh) return;
      for (const material of Array.isArray(object.material) ? object.material : [object.material]) decodeLambertLightmap(material);
    });
  }
}
