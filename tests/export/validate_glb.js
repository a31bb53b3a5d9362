// Runs the Khronos glTF-Validator (npm package `gltf-validator`) over the .glb files named on
// the command line and prints one JSON line per file: its name, the numbers of errors,
// warnings, infos and hints, and the messages of the errors and warnings. Used by
// tests/export.rs; the folder holding node_modules/gltf-validator comes from NODE_PATH.
"use strict";
const fs = require("fs");
const validator = require("gltf-validator");

async function main() {
  for (const file of process.argv.slice(2)) {
    const bytes = new Uint8Array(fs.readFileSync(file));
    const report = await validator.validateBytes(bytes, { maxIssues: 100 });
    const issues = report.issues;
    const serious = issues.messages.filter((m) => m.severity <= 1);
    console.log(
      JSON.stringify({
        file,
        validator: report.validatorVersion,
        errors: issues.numErrors,
        warnings: issues.numWarnings,
        infos: issues.numInfos,
        hints: issues.numHints,
        messages: serious,
      })
    );
  }
}

main().catch((e) => {
  console.error(String(e));
  process.exit(2);
});
