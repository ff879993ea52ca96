// Runs the Khronos glTF-Validator on .glb files: prints each issue and exits 1 if there is any
// error, warning or info. Usage: node tests/validate-glb.js VALIDATOR_MODULE_DIR FILE...
// The one vendor extension lambert writes, LAMBERT_lightmap (src/lambert/io/lightmap_export.h),
// is unknown to the validator, which says so (UNSUPPORTED_EXTENSION), notes that its prefix is not
// in Khronos's registry (UNRESERVED_EXTENSION_PREFIX) and, not seeing what the extension uses,
// calls its textures and its primitives' lightmap coordinates (and the sets below them, which
// glTF requires) unused (UNUSED_OBJECT). Those are shown and not counted; every other issue
// counts, an unknown extension other than LAMBERT_lightmap included.
const validator = require(process.argv[2]);
const fs = require('fs');

// The JSON pointers of what the file's LAMBERT_lightmap materials use.
function lightmapUses(bytes) {
  const used = new Set();
  if (bytes.length < 20 || bytes.toString('latin1', 0, 4) !== 'glTF') return used;
  const json = JSON.parse(bytes.toString('utf8', 20, 20 + bytes.readUInt32LE(12)));
  const lightmap = (m) => (m && m.extensions && m.extensions.LAMBERT_lightmap) || null;
  for (const m of json.materials || []) if (lightmap(m)) used.add(`/textures/${lightmap(m).index}`);
  (json.meshes || []).forEach((mesh, i) => mesh.primitives.forEach((p, j) => {
    const e = p.material === undefined ? null : lightmap(json.materials[p.material]);
    // Its set, and those below it, which glTF requires to exist (numbered from 0 without gaps).
    for (let k = 0; e && k <= (e.texCoord === undefined ? 0 : e.texCoord); ++k) used.add(`/meshes/${i}/primitives/${j}/attributes/TEXCOORD_${k}`);
  }));
  return used;
}

(async () => {
  let issues = 0;
  for (const file of process.argv.slice(3)) {
    const bytes = fs.readFileSync(file);
    const report = await validator.validateBytes(new Uint8Array(bytes));
    const n = report.issues;
    const used = lightmapUses(bytes);
    console.log(`${file}: ${n.numErrors} errors, ${n.numWarnings} warnings, ${n.numInfos} infos (validator ${validator.version()})`);
    for (const m of n.messages) {
      const vendor = (['UNSUPPORTED_EXTENSION', 'UNRESERVED_EXTENSION_PREFIX'].includes(m.code) && m.message.includes("LAMBERT")) ||
                     (m.code === 'UNUSED_OBJECT' && used.has(m.pointer));
      console.log(`  ${m.code} at ${m.pointer}: ${m.message}${vendor ? ' (LAMBERT_lightmap: not counted)' : ''}`);
      if (!vendor && m.severity <= 2) issues += 1;  // 0 error, 1 warning, 2 info (3, hints, never counted)
    }
  }
  process.exit(issues > 0 ? 1 : 0);
})();
