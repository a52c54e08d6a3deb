#!/usr/bin/env node
// A KHR_draco_mesh_compression file decoded by Google's own Draco decoder (the draco3dgltf
// package's WebAssembly build, which glTF-Transform uses) and written back uncompressed: the
// same triangles in the same order, an independent decoder's twin of the file for smlt's.
//
//     NODE_PATH=…/node_modules node draco_decode.cjs IN.gltf OUT.gltf
//
// Needs `npm install @gltf-transform/cli` (which brings @gltf-transform/core, /extensions and
// draco3dgltf); NODE_PATH names the node_modules folder it was installed in.
const { NodeIO } = require("@gltf-transform/core");
const { ALL_EXTENSIONS } = require("@gltf-transform/extensions");
const draco3d = require("draco3dgltf");
const fs = require("fs");
const path = require("path");

async function main() {
  const [input, output] = process.argv.slice(2);
  if (!input || !output) {
    console.error("usage: draco_decode.cjs IN.gltf OUT.gltf");
    process.exit(2);
  }
  const io = new NodeIO()
    .registerExtensions(ALL_EXTENSIONS)
    .registerDependencies({ "draco3d.decoder": await draco3d.createDecoderModule() });
  const doc = await io.read(input);
  const draco = doc.getRoot().listExtensionsUsed().filter((e) => e.extensionName === "KHR_draco_mesh_compression");
  if (draco.length === 0) {
    console.error(`${input} does not use KHR_draco_mesh_compression`);
    process.exit(1);
  }
  draco.forEach((e) => e.dispose());
  fs.mkdirSync(path.dirname(path.resolve(output)), { recursive: true });
  await io.write(output, doc);
}

main().catch((e) => {
  console.error(e.message);
  process.exit(1);
});
