// Runs the Khronos glTF-Validator on .glb files: prints each issue and exits 1 if there is any
// error, warning or info. Usage: node tests/validate-glb.js VALIDATOR_MODULE_DIR FILE...
const validator = require(process.argv[2]);
const fs = require('fs');
(async () => {
  let issues = 0;
  for (const file of process.argv.slice(3)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)));
    const n = report.issues;
    console.log(`${file}: ${n.numErrors} errors, ${n.numWarnings} warnings, ${n.numInfos} infos (validator ${validator.version()})`);
    for (const m of n.messages) console.log(`  ${m.code} at ${m.pointer}: ${m.message}`);
    issues += n.numErrors + n.numWarnings + n.numInfos;
  }
  process.exit(issues > 0 ? 1 : 0);
})();
