// build.mjs — bundle the dashboard (src/) into ../web_static/ with esbuild:
// app.js (ES module, minified, with source map), app.css (our styles + uPlot's),
// index.html copied as is. Run by `make web`; output is gitignored.
import * as esbuild from 'esbuild';
import { copyFileSync, mkdirSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const out = process.env.WEB_OUT || join(here, '..', 'web_static');
mkdirSync(out, { recursive: true });
await esbuild.build({
  entryPoints: { app: join(here, 'src', 'main.js') },
  bundle: true,
  format: 'esm',
  target: ['chrome100', 'firefox100', 'safari15'],
  minify: true,
  sourcemap: true,
  outdir: out,
  logLevel: 'warning',
});
copyFileSync(join(here, 'src', 'index.html'), join(out, 'index.html'));
console.log(`  WEB     ${out}/{index.html,app.js,app.css}`);
