#!/usr/bin/env node
// A glTF file's PNG, JPEG and WebP textures compressed to KTX2 with Basis Universal data
// (KHR_texture_basisu, marked required), by Binomial's own encoder: the ktx2-encoder package's
// WebAssembly build of basis_universal (what its glTF-Transform transform does, here with one
// glTF-Transform module instance).
//
//     NODE_PATH=…/node_modules node ktx2_encode.mjs IN.gltf OUT.gltf [--uastc] [--zstd] [--mipmaps]
//
// ETC1S (BasisLZ) by default; --uastc for UASTC, --zstd to Zstandard-supercompress it; the
// DFD's transfer function sRGB for colour textures, linear for the others (the spec's rule). Needs
// `npm install @gltf-transform/cli ktx2-encoder@0.6.0` (the CLI brings sharp, which decodes the
// source images); NODE_PATH names the node_modules folder they were installed in.
import { createRequire } from "module";
import fs from "fs";
import path from "path";
import { pathToFileURL } from "url";

const require = createRequire(path.join(process.env.NODE_PATH ?? ".", "_"));
const { NodeIO } = require("@gltf-transform/core");
const { ALL_EXTENSIONS, KHRTextureBasisu } = require("@gltf-transform/extensions");
const sharp = require("sharp");
// The package exports an ES module only, which NODE_PATH does not resolve.
const encoder = path.join(process.env.NODE_PATH ?? "node_modules", "ktx2-encoder/dist/node/index.js");
const { encodeToKTX2 } = await import(pathToFileURL(encoder).href);

const args = process.argv.slice(2);
const [input, output] = args.filter((a) => !a.startsWith("--"));
if (!input || !output) {
  console.error("usage: ktx2_encode.mjs IN.gltf OUT.gltf [--uastc] [--zstd] [--mipmaps]");
  process.exit(2);
}
const imageDecoder = async (buffer) => {
  const { data, info } = await sharp(buffer).ensureAlpha().raw().toBuffer({ resolveWithObject: true });
  return { data: new Uint8Array(data), width: info.width, height: info.height };
};
const io = new NodeIO().registerExtensions(ALL_EXTENSIONS);
const doc = await io.read(input);
// The spec's DFD: an sRGB transfer function for colour textures, linear for the rest.
const COLOUR_SLOTS = ["baseColorTexture", "emissiveTexture", "specularColorTexture", "sheenColorTexture"];
const graph = doc.getGraph();
for (const texture of doc.getRoot().listTextures()) {
  if (!["image/png", "image/jpeg", "image/webp"].includes(texture.getMimeType())) continue;
  const slots = graph.listParentEdges(texture).map((edge) => edge.getName());
  const options = {
    isUASTC: args.includes("--uastc"),
    needSupercompression: args.includes("--zstd"),
    generateMipmap: args.includes("--mipmaps"),
    isSetKTX2SRGBTransferFunc: slots.some((slot) => COLOUR_SLOTS.includes(slot)),
    isNormalMap: slots.includes("normalTexture"),
    imageDecoder,
  };
  texture.setImage(await encodeToKTX2(texture.getImage(), options)).setMimeType("image/ktx2");
  texture.setURI(texture.getURI().replace(/\.(png|jpe?g|webp)$/, ".ktx2"));
}
doc.createExtension(KHRTextureBasisu).setRequired(true);
const left = doc.getRoot().listTextures().filter((t) => t.getMimeType() !== "image/ktx2");
if (left.length > 0) {
  console.error(`${left.length} textures were not compressed`);
  process.exit(1);
}
fs.mkdirSync(path.dirname(path.resolve(output)), { recursive: true });
await io.write(output, doc);
