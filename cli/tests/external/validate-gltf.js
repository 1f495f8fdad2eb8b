// Runs the Khronos glTF validator (npm `gltf-validator`, Apache-2.0) on each
// file named and prints one JSON line per file: its counts of errors,
// warnings, infos and hints and every message (code, pointer, text).
// Written for ufcsr's tests (tests/external/gltf_validator.rs); usage:
//   NODE_PATH=<folder holding node_modules> node validate-gltf.js FILE.glb ...
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

async function validate(file) {
  const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: (uri) =>
      Promise.reject(`ufcsr files embed everything; ${uri} is an external resource`),
  });
  const issues = report.issues;
  const severity = ['error', 'warning', 'info', 'hint'];
  return {
    file,
    errors: issues.numErrors,
    warnings: issues.numWarnings,
    infos: issues.numInfos,
    hints: issues.numHints,
    messages: issues.messages.map((m) => `${severity[m.severity]} ${m.code} at ${m.pointer || '-'}: ${m.message}`),
  };
}

(async () => {
  for (const file of process.argv.slice(2)) {
    console.log(JSON.stringify(await validate(file)));
  }
})().catch((e) => {
  console.error(String(e));
  process.exit(2);
});
