// Validates one .gltf or .glb file with the Khronos glTF-Validator and prints
// its report as JSON: node validate.mjs FILE. External resources are read
// from beside the file.
import { readFile } from "node:fs/promises";
import path from "node:path";
import validator from "gltf-validator";

const file = process.argv[2];
const bytes = new Uint8Array(await readFile(file));
const report = await validator.validateBytes(bytes, {
  uri: path.basename(file),
  externalResourceFunction: (uri) =>
    readFile(path.join(path.dirname(file), decodeURIComponent(uri))).then((data) => new Uint8Array(data)),
});
console.log(JSON.stringify(report));
