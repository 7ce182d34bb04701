// Runs the Khronos glTF validator on files StarCages wrote (baked animations, GLB exports) and
// prints every error and warning; exits with status 1 when there is one.
//
// The validator is not a project dependency: install it outside the project
// (`mkdir /tmp/gv && cd /tmp/gv && npm install gltf-validator`), then
//     NODE_PATH=/tmp/gv/node_modules node scripts/validate_gltf.js FILE.glb [FILE.gltf ...]
const validator = require('gltf-validator');
const fs = require('fs');
const path = require('path');

async function main() {
  let failed = false;
  for (const file of process.argv.slice(2)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
      maxIssues: 100,
      externalResourceFunction: (uri) =>
        Promise.resolve(new Uint8Array(fs.readFileSync(path.join(path.dirname(file), decodeURI(uri))))),
    });
    const issues = report.issues;
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
      `${issues.numInfos} infos, ${issues.numHints} hints`);
    for (const m of issues.messages) {
      if (m.severity <= 1) console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code}: ${m.message} at ${m.pointer}`);
    }
    failed = failed || issues.numErrors > 0 || issues.numWarnings > 0;
  }
  process.exit(failed ? 1 : 0);
}
main();
