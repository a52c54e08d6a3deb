#!/usr/bin/env node
// A KHR_texture_basisu file's KTX2 images transcoded to RGBA by Binomial's own Basis Universal
// transcoder (three.js's WebAssembly build of it, examples/jsm/libs/basis) and written back as
// PNG without the extension: an independent decoder's twin of the file for smlt's.
//
//     NODE_PATH=…/node_modules node ktx2_decode.cjs IN.gltf OUT.gltf
//
// Needs `npm install @gltf-transform/cli three@0.170.0` (the CLI brings sharp, which writes the
// PNGs); NODE_PATH names the node_modules folder they were installed in.
const { NodeIO } = require("@gltf-transform/core");
const { ALL_EXTENSIONS } = require("@gltf-transform/extensions");
const sharp = require("sharp");
const fs = require("fs");
const path = require("path");

// three.js ships the transcoder as an Emscripten module (a CommonJS script in an ES-module
// package, so run here as CommonJS); its `KTX2File` reads a KTX2 file.
function loadTranscoder() {
  const file = path.join(path.dirname(require.resolve("three")), "../examples/jsm/libs/basis/basis_transcoder.js");
  const module = { exports: {} };
  new Function("module", "exports", "require", "__filename", "__dirname", fs.readFileSync(file, "utf8"))(
    module, module.exports, require, file, path.dirname(file));
  return module.exports;
}
const RGBA32 = 13; // transcoder_texture_format::cTFRGBA32

async function main() {
  const [input, output] = process.argv.slice(2);
  if (!input || !output) {
    console.error("usage: ktx2_decode.cjs IN.gltf OUT.gltf");
    process.exit(2);
  }
  const basis = await loadTranscoder()();
  basis.initializeBasis();
  const io = new NodeIO().registerExtensions(ALL_EXTENSIONS);
  const doc = await io.read(input);
  const textures = doc.getRoot().listTextures().filter((t) => t.getMimeType() === "image/ktx2");
  if (textures.length === 0) {
    console.error(`${input} has no KTX2 image`);
    process.exit(1);
  }
  for (const texture of textures) {
    const file = new basis.KTX2File(new Uint8Array(texture.getImage()));
    try {
      if (!file.isValid() || !file.startTranscoding()) throw new Error(`${texture.getURI()}: not a valid KTX2 file`);
      const width = file.getWidth();
      const height = file.getHeight();
      const rgba = new Uint8Array(file.getImageTranscodedSizeInBytes(0, 0, 0, RGBA32));
      if (!file.transcodeImage(rgba, 0, 0, 0, RGBA32, 0, -1, -1)) throw new Error(`${texture.getURI()}: does not transcode`);
      const png = await sharp(Buffer.from(rgba), { raw: { width, height, channels: 4 } }).png().toBuffer();
      texture.setImage(new Uint8Array(png)).setMimeType("image/png");
      texture.setURI(texture.getURI().replace(/\.ktx2$/, ".png"));
    } finally {
      file.close();
      file.delete();
    }
  }
  doc.getRoot().listExtensionsUsed().filter((e) => e.extensionName === "KHR_texture_basisu").forEach((e) => e.dispose());
  fs.mkdirSync(path.dirname(path.resolve(output)), { recursive: true });
  await io.write(output, doc);
}

main().catch((e) => {
  console.error(e.message);
  process.exit(1);
});
