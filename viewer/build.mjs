// Builds mbgc-view.html: bundles src/viewer.js with three.js, GLTFLoader and
// OrbitControls into one script and puts it inside src/index.html, so the
// page fetches nothing when it is opened (it works offline, from file://).
//
//   node build.mjs SRC_DIR OUT.html      (run from the folder holding node_modules)
//
// Why a bundler, and why esbuild: three.js's modules import each other
// (three.module.js imports ./three.core.js, the addons import 'three'), and
// an inlined <script type="module"> cannot resolve those imports, so the
// modules must be joined into one script at build time. esbuild does that in
// well under a second, is one npm package with a prebuilt binary and no
// dependency tree, and is widely used and actively kept.
import { build } from 'esbuild';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';

const [src, out] = process.argv.slice(2);
if (!src || !out) {
  console.error('usage: node build.mjs SRC_DIR OUT.html');
  process.exit(2);
}

const bundle = await build({
  entryPoints: [join(src, 'viewer.js')],
  bundle: true,
  format: 'esm',
  minify: true,
  target: 'es2020',
  legalComments: 'eof',  // keeps three.js's MIT licence notice in the file
  write: false,
  nodePaths: [join(process.cwd(), 'node_modules')],  // the sources are in the source tree, the packages in the build tree
});
// Inside <script>, the text "</script" would end the element and "<!--" can
// change how the HTML parser reads it; escaped, the JavaScript is the same.
const script = bundle.outputFiles[0].text.replaceAll('</script', '<\\/script').replaceAll('<!--', '<\\!--');

const page = readFileSync(join(src, 'index.html'), 'utf8');
if (!page.includes('<!-- BUNDLE -->')) throw new Error(`${src}/index.html has no <!-- BUNDLE --> placeholder`);
const html = page.replace('<!-- BUNDLE -->', () => `<script type="module">\n${script}</script>`);
writeFileSync(out, html);
console.log(`${out}: ${(html.length / 1024).toFixed(0)} kB`);
