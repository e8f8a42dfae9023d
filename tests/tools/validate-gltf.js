#!/usr/bin/env node
// The Khronos glTF validator (npm gltf-validator) on one .gltf or .glb file, with external
// resources (.bin, images) read from the file's folder. Prints one line
//   FILE: N errors, N warnings, N infos, N hints
// then one line per error and warning (code, JSON pointer, message); exit 0 when the file has
// no error and no warning, 1 when it has any, 2 when it cannot run. The module is found through
// NODE_PATH or GLTF_VALIDATOR_DIR (default /opt/gltf-validator/node_modules).
'use strict';
const fs = require('fs');
const path = require('path');
let validator;
try {
  validator = require('gltf-validator');
} catch (e) {
  const dir = process.env.GLTF_VALIDATOR_DIR || '/opt/gltf-validator/node_modules';
  try {
    validator = require(path.join(dir, 'gltf-validator'));
  } catch (e2) {
    console.error('validate-gltf: gltf-validator not found (npm install --prefix /opt/gltf-validator gltf-validator)');
    process.exit(2);
  }
}
const file = process.argv[2];
if (!file) {
  console.error('usage: validate-gltf.js FILE.gltf|FILE.glb');
  process.exit(2);
}
const bytes = new Uint8Array(fs.readFileSync(file));
const folder = path.dirname(file);
validator.validateBytes(bytes, {
  uri: path.basename(file),
  maxIssues: 1000,
  externalResourceFunction: (uri) => new Promise((resolve, reject) => {
    const p = path.join(folder, decodeURIComponent(uri));
    fs.readFile(p, (err, data) => err ? reject(err.toString()) : resolve(new Uint8Array(data)));
  }),
}).then((report) => {
  const i = report.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ` +
              `${i.numHints} hints`);
  for (const m of i.messages)
    if (m.severity <= 1)
      console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} ${m.pointer || ''}: ${m.message}`);
  if (process.env.VALIDATE_GLTF_VERBOSE)
    for (const m of i.messages)
      if (m.severity > 1) console.log(`  info ${m.code} ${m.pointer || ''}: ${m.message}`);
  process.exit(i.numErrors + i.numWarnings > 0 ? 1 : 0);
}, (err) => {
  console.error(`validate-gltf: ${file}: ${err}`);
  process.exit(2);
});
