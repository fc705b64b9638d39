// check_docs.mjs — keeps the documentation honest (ctest label `docs`;
// tests/README.md, "Documentation tests", describes the conventions).
//
//   node check_docs.mjs snippets --mbgc MBGC --root REPO --work DIR FILE.md...
//       compiles every ```mbg block of each file with mbgc; a block marked
//       <!-- mbg: error "TEXT" --> must fail with TEXT in mbgc's message
//   node check_docs.mjs commands --root REPO --work DIR --build-demo BUILD FILE.md...
//       runs every ```sh block marked <!-- sh: run --> with bash, in a fresh
//       folder where the repository's top-level entries and build-demo/
//       (BUILD) are links: the README's quick start, by hand
//   node check_docs.mjs paths --root REPO FILE.md...
//       every repository path a file names (examples/x/y.mbg, tools/foo.sh,
//       docs/bar.md, relative links [..](file)) must exist
//
// Exit status 0 when everything holds, 1 otherwise (each problem printed as
// FILE:LINE: ...), 2 on a bad command line.
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';

function usage(msg) {
  console.error(`check_docs.mjs: ${msg}`);
  process.exit(2);
}

function parseArgs(argv) {
  const o = { files: [] };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === '--mbgc' || a === '--root' || a === '--work' || a === '--build-demo') {
      if (i + 1 >= argv.length) usage(`${a} needs a value`);
      o[a.slice(2).replace('-', '_')] = argv[++i];
    } else if (a.startsWith('--')) {
      usage(`unknown option ${a}`);
    } else {
      o.files.push(a);
    }
  }
  return o;
}

// ---------------------------------------------------------------------------
// Fenced blocks and the directive comment before each.

// Splits a directive's words: spaces separate, "double quotes" group.
function words(s) {
  const out = [];
  const re = /"((?:[^"\\]|\\.)*)"|(\S+)/g;
  let m;
  while ((m = re.exec(s))) out.push(m[1] !== undefined ? m[1].replace(/\\(.)/g, '$1') : m[2]);
  return out;
}

// Every fenced block: { lang, line (1-based, of the opening fence), text,
// directive: { words, body } | null }.
function fencedBlocks(lines) {
  const blocks = [];
  for (let i = 0; i < lines.length; i++) {
    const open = /^(\s*)(`{3,}|~{3,})\s*([^\s`]*)\s*$/.exec(lines[i]);
    if (!open) continue;
    const fence = open[2];
    const body = [];
    let j = i + 1;
    for (; j < lines.length; j++) {
      const close = new RegExp(`^\\s*${fence[0] === '`' ? '`' : '~'}{${fence.length},}\\s*$`);
      if (close.test(lines[j])) break;
      body.push(lines[j].startsWith(open[1]) ? lines[j].slice(open[1].length) : lines[j]);
    }
    blocks.push({ lang: open[3], line: i + 1, text: body.join('\n') + '\n', directive: directiveBefore(lines, i),
                  unclosed: j >= lines.length });
    i = j;
  }
  return blocks;
}

// The `<!-- mbg: ... -->` comment that ends on the last non-blank line before
// line index `at`, if any: its first line's words and the lines after it.
function directiveBefore(lines, at) {
  let k = at - 1;
  while (k >= 0 && lines[k].trim() === '') k--;
  if (k < 0 || !lines[k].trimEnd().endsWith('-->')) return null;
  let s = k;
  while (s >= 0 && !lines[s].includes('<!--')) s--;
  if (s < 0) return null;
  const sh = /<!--\s*sh:\s*run\s*-->/.test(lines[s]);
  if (sh) return { words: ['run'], body: [], line: s + 1, sh: true };
  const m = /<!--\s*mbg:(.*)$/.exec(lines[s]);
  if (!m) return null;
  const comment = lines.slice(s, k + 1);
  comment[0] = m[1];
  comment[comment.length - 1] = comment[comment.length - 1].replace(/-->\s*$/, '');
  return { words: words(comment[0]), body: comment.slice(1), line: s + 1 };
}

// ---------------------------------------------------------------------------
// snippets

function checkSnippets(o) {
  if (!o.mbgc || !o.root || !o.work) usage('snippets needs --mbgc, --root and --work');
  const root = path.resolve(o.root);
  let checked = 0;
  const problems = [];
  for (const file of o.files) {
    const rel = path.relative(root, path.resolve(file));
    const lines = fs.readFileSync(file, 'utf8').split('\n');
    for (const b of fencedBlocks(lines)) {
      const where = `${rel}:${b.line}`;
      if (b.unclosed) {
        problems.push(`${where}: a code block that is never closed`);
        continue;
      }
      if (b.lang === '') {
        problems.push(`${where}: a code block without a language: write \`\`\`mbg for a model, \`\`\`sh for commands, \`\`\`text for anything else`);
        continue;
      }
      if (b.directive && b.lang !== 'mbg' && !(b.lang === 'sh' && b.directive.sh)) {
        problems.push(`${where}: an <!-- mbg: --> comment before a \`\`\`${b.lang} block (only \`\`\`mbg blocks are compiled)`);
        continue;
      }
      if (b.lang !== 'mbg') continue;
      checked++;
      const p = compileSnippet(o, root, rel, b);
      if (p) problems.push(`${where}: ${p}`);
    }
  }
  for (const p of problems) console.log(p);
  if (problems.length) {
    console.log(`FAILED: ${problems.length} problem(s); ${checked} model snippet(s) in ${o.files.length} file(s)`);
    return 1;
  }
  console.log(`ok: ${checked} model snippet(s) in ${o.files.length} file(s) compile as they say`);
  return 0;
}

// Compiles one block; returns a problem's text or null.
function compileSnippet(o, root, rel, b) {
  const opts = [];
  let expectError = null;
  let fragment = false;
  let beside = null;
  const w = b.directive ? b.directive.words : [];
  for (let i = 0; i < w.length; i++) {
    if (w[i] === 'error') {
      if (i + 1 >= w.length) return 'mbg: error needs the "text" of the message';
      expectError = w[++i];
    } else if (w[i] === 'fragment') {
      fragment = true;
    } else if (w[i] === 'beside') {
      if (i + 1 >= w.length) return 'mbg: beside needs a folder';
      beside = w[++i];
    } else if (w[i] === '-I') {
      if (i + 1 >= w.length) return 'mbg: -I needs a folder';
      opts.push('-I', path.join(root, w[++i]));
    } else if (w[i].startsWith('-')) {
      opts.push(w[i]);
      if (i + 1 < w.length && !w[i + 1].startsWith('-') && !w[i].includes('=')) opts.push(w[++i]);
    } else {
      return `mbg: unknown word \`${w[i]}\` (known: fragment, error "TEXT", beside DIR, -I DIR, mbgc options)`;
    }
  }
  if (b.directive && b.directive.body.some((l) => l.trim() !== '') && !fragment)
    return 'the <!-- mbg: --> comment has lines of model text but does not say `fragment`';

  let text = b.text;
  let before = 0; // lines of the fragment's model before the snippet
  if (fragment) {
    const ctx = b.directive.body;
    const at = ctx.findIndex((l) => l.trim() === '...');
    before = at < 0 ? ctx.length : at;
    text = at < 0 ? ctx.join('\n') + '\n' + b.text
                  : ctx.slice(0, at).join('\n') + '\n' + b.text + ctx.slice(at + 1).join('\n') + '\n';
  }
  const snippetLines = b.text.split('\n').length - 1;

  const dir = path.join(o.work, rel.replace(/[\\/]/g, '_') + `_${b.line}`);
  fs.rmSync(dir, { recursive: true, force: true });
  fs.mkdirSync(dir, { recursive: true });
  if (beside) {
    const from = path.join(root, beside);
    if (!fs.existsSync(from) || !fs.statSync(from).isDirectory()) return `mbg: beside ${beside}: no such folder`;
    for (const f of fs.readdirSync(from)) {
      const src = path.join(from, f);
      if (fs.statSync(src).isFile()) fs.copyFileSync(src, path.join(dir, f));
    }
  }
  const model = path.join(dir, 'snippet.mbg');
  fs.writeFileSync(model, text);
  const args = [model, '-o', path.join(dir, 'snippet.cpp'), ...opts];
  const r = spawnSync(o.mbgc, args, { encoding: 'utf8', timeout: 120000 });
  if (r.error) return `could not run ${o.mbgc}: ${r.error.message}`;
  // mbgc's positions in the snippet's lines as positions in the page
  const said = (r.stdout + r.stderr).trim().split(model).join('snippet.mbg').replace(
      /snippet\.mbg:(\d+):(\d+)/g, (m, l, c) => {
        const k = Number(l) - before;
        return k >= 1 && k <= snippetLines ? `${rel}:${b.line + k}:${c}` : `${m} (the fragment's hidden lines)`;
      });
  const cmd = `mbgc ${args.map((a) => path.relative(process.cwd(), a) || a).join(' ')}`;
  const show = (s) => s.split('\n').slice(0, 12).map((l) => '    ' + l).join('\n');
  if (expectError === null) {
    if (r.status !== 0)
      return `this model snippet does not compile (${cmd}, exit status ${r.status}):\n${show(said)}\n  (text compiled: ${model})`;
    return null;
  }
  if (r.status === 0) return `marked mbg: error "${expectError}", but it compiles (${cmd})`;
  if (r.status !== 1) return `marked mbg: error "${expectError}": mbgc exited with status ${r.status}, not 1 (${cmd}):\n${show(said)}`;
  if (!said.includes(expectError))
    return `marked mbg: error "${expectError}", but mbgc says something else (${cmd}):\n${show(said)}`;
  return null;
}

// ---------------------------------------------------------------------------
// commands

function runCommands(o) {
  if (!o.root || !o.work || !o.build_demo) usage('commands needs --root, --work and --build-demo');
  const root = path.resolve(o.root);
  let ran = 0;
  const problems = [];
  for (const file of o.files) {
    const rel = path.relative(root, path.resolve(file));
    const lines = fs.readFileSync(file, 'utf8').split('\n');
    for (const b of fencedBlocks(lines)) {
      if (!(b.directive && b.directive.sh)) continue;
      if (b.lang !== 'sh') {
        problems.push(`${rel}:${b.line}: <!-- sh: run --> before a \`\`\`${b.lang} block`);
        continue;
      }
      ran++;
      const dir = path.join(o.work, rel.replace(/[\\/]/g, '_') + `_${b.line}`);
      fs.rmSync(dir, { recursive: true, force: true });
      fs.mkdirSync(dir, { recursive: true });
      for (const e of fs.readdirSync(root)) {
        if (e === '.git' || /^build/.test(e)) continue;
        fs.symlinkSync(path.join(root, e), path.join(dir, e));
      }
      fs.symlinkSync(path.resolve(o.build_demo), path.join(dir, 'build-demo'));
      console.log(`${rel}:${b.line}: running in ${dir}:\n${b.text.replace(/^/gm, '  $ ').trimEnd()}`);
      const r = spawnSync('bash', ['-euo', 'pipefail', '-c', b.text], { cwd: dir, encoding: 'utf8', timeout: 600000 });
      const said = ((r.stdout || '') + (r.stderr || '')).trim().split('\n').slice(-20).map((l) => '    ' + l).join('\n');
      if (r.error) problems.push(`${rel}:${b.line}: could not run bash: ${r.error.message}`);
      else if (r.status !== 0) problems.push(`${rel}:${b.line}: these commands fail (exit status ${r.status}):\n${said}`);
    }
  }
  for (const p of problems) console.log(p);
  if (problems.length) {
    console.log(`FAILED: ${problems.length} block(s) of commands fail, of ${ran}`);
    return 1;
  }
  console.log(`ok: ${ran} block(s) of commands run`);
  return 0;
}

// ---------------------------------------------------------------------------
// paths

// Every file and folder of the repository (not build trees, .git, node_modules).
function repoEntries(root) {
  const entries = new Set();
  const skip = new Set(['.git', 'node_modules']);
  const walk = (dir, rel) => {
    let list = [];
    try {
      list = fs.readdirSync(dir, { withFileTypes: true });
    } catch {
      return; // a folder removed while we walk (another build's temporary files)
    }
    for (const d of list) {
      if (skip.has(d.name) || (rel === '' && /^build/.test(d.name))) continue;
      const r = rel ? `${rel}/${d.name}` : d.name;
      if (d.isDirectory()) {
        entries.add(r + '/');
        walk(path.join(dir, d.name), r);
      } else {
        entries.add(r);
      }
    }
  };
  walk(root, '');
  return entries;
}

// `a{b,c}d` -> [abd, acd] (one level, repeated).
function expandBraces(s) {
  const m = /\{([^{}]*,[^{}]*)\}/.exec(s);
  if (!m) return [s];
  return m[1].split(',').flatMap((alt) => expandBraces(s.slice(0, m.index) + alt + s.slice(m.index + m[0].length)));
}

function globRegex(p) {
  let re = '';
  for (let i = 0; i < p.length; i++) {
    const c = p[i];
    if (c === '*' && p[i + 1] === '*') { re += '.*'; i++; }
    else if (c === '*') re += '[^/]*';
    else if (c === '?') re += '[^/]';
    else re += c.replace(/[.+^${}()|[\]\\]/g, '\\$&');
  }
  return new RegExp(`^${re}/?$`);
}

// Whether a repository path exists: a file or folder of that name; a
// pattern (*, **, {a,b}, a NAME-like segment in capitals) matching one; or,
// for a last segment without an extension, a file of that name with one
// (a golden test named without its .mbg).
function pathExists(entries, p) {
  p = p.replace(/\/+$/, '');
  return expandBraces(p).every((q) => {
    q = q.replace(/(?<![A-Za-z])[A-Z][A-Z_]+(?![A-Za-z])/g, (w) => (w === 'README' ? w : '*'));
    if (!/[*?]/.test(q)) {
      if (entries.has(q) || entries.has(q + '/')) return true;
      if (!/\.[^/]*$/.test(q)) return [...entries].some((e) => e.startsWith(q + '.') && !e.slice(q.length + 1).includes('/'));
      return false;
    }
    const re = globRegex(q);
    return [...entries].some((e) => re.test(e));
  });
}

// The anchors of a markdown file's headings, as GitHub makes them: lower
// case, punctuation dropped but for - and _, spaces as -, a repeated one
// with -1, -2, ...
const anchorCache = new Map();
function anchors(file) {
  if (anchorCache.has(file)) return anchorCache.get(file);
  const seen = new Map();
  const set = new Set();
  let fence = false;
  for (const line of fs.readFileSync(file, 'utf8').split('\n')) {
    if (/^\s*(```|~~~)/.test(line)) fence = !fence;
    const h = !fence && /^#{1,6}\s+(.*?)\s*#*\s*$/.exec(line);
    if (!h) continue;
    const slug = h[1].toLowerCase().replace(/[^\p{L}\p{N}\s_-]/gu, '').replace(/\s/g, '-');
    const n = seen.get(slug) || 0;
    seen.set(slug, n + 1);
    set.add(n ? `${slug}-${n}` : slug);
  }
  anchorCache.set(file, set);
  return set;
}

function checkPaths(o) {
  if (!o.root) usage('paths needs --root');
  const root = path.resolve(o.root);
  const entries = repoEntries(root);
  // the repository's top-level names: a path starting with one is a repository path
  const top = [...entries].filter((e) => !e.slice(0, -1).includes('/')).map((e) => e.replace(/\/$/, ''));
  const dirs = top.filter((t) => entries.has(t + '/')).map((t) => t.replace(/[.]/g, '\\.'));
  const pathRe = new RegExp(`(?<![\\w./~$-])((?:${dirs.join('|')})/[\\w.{},*/+-]*)`, 'g');
  const problems = [];
  let named = 0;
  for (const file of o.files) {
    const abs = path.resolve(file);
    const rel = path.relative(root, abs);
    const lines = fs.readFileSync(abs, 'utf8').split('\n');
    lines.forEach((line, n) => {
      const where = `${rel}:${n + 1}`;
      // relative links and images: [text](target), relative to the file;
      // an #anchor must be a heading of the page it points into
      for (const m of line.matchAll(/\]\(([^)\s]+)(?:\s+"[^"]*")?\)/g)) {
        if (/^[a-z][a-z0-9+.-]*:/i.test(m[1])) continue;
        const [target, anchor] = m[1].split('#');
        named++;
        const file = target === '' ? abs : path.resolve(path.dirname(abs), decodeURIComponent(target));
        const r = path.relative(root, file);
        if (r.startsWith('..')) problems.push(`${where}: the link ${m[1]} leaves the repository`);
        else if (!pathExists(entries, r)) problems.push(`${where}: the link ${m[1]} names ${r}, which does not exist`);
        else if (anchor !== undefined && r.endsWith('.md') && !anchors(file).has(anchor))
          problems.push(`${where}: the link ${m[1]}: ${r} has no heading #${anchor}`);
      }
      // paths from the repository's root, in text or code
      for (const m of line.matchAll(pathRe)) {
        let p = m[1].replace(/[.,:;]+$/, '');
        named++;
        if (!pathExists(entries, p)) problems.push(`${where}: names ${p}, which does not exist`);
      }
      // files outside the repository
      if (/(^|[\s`(])\.\.\/shared\//.test(line)) problems.push(`${where}: names a file outside the repository (../shared/)`);
    });
  }
  for (const p of problems) console.log(p);
  if (problems.length) {
    console.log(`FAILED: ${problems.length} path(s) that do not exist, of ${named} named in ${o.files.length} file(s)`);
    return 1;
  }
  console.log(`ok: the ${named} repository path(s) named in ${o.files.length} file(s) exist`);
  return 0;
}

const [mode, ...rest] = process.argv.slice(2);
const o = parseArgs(rest);
if (!o.files.length) usage('no markdown files given');
if (mode === 'snippets') process.exit(checkSnippets(o));
else if (mode === 'paths') process.exit(checkPaths(o));
else if (mode === 'commands') process.exit(runCommands(o));
else usage('the first argument is `snippets`, `commands` or `paths`');
