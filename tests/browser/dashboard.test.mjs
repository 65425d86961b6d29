/**
 * Browser tests of the dashboard (/ui/): a real `uniphys serve` with a fresh data directory,
 * seeded through the API with two example assets and a corrupt file, driven by Debian's headless
 * Chromium through playwright-core (which downloads no browser).
 *
 *   UNIPHYS_BIN=$PWD/target/debug/uniphys npm --prefix tests/browser test
 *
 * Environment: UNIPHYS_BIN (required), CHROMIUM_PATH (default /usr/bin/chromium),
 * BROWSER_ARTIFACTS_DIR (screenshots; default <repo>/target/browser-artifacts).
 */

import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { once } from 'node:events';
import { mkdir, mkdtemp, readFile, rm } from 'node:fs/promises';
import { createServer } from 'node:net';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { createInterface } from 'node:readline';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const REPO = resolve(dirname(fileURLToPath(import.meta.url)), '..', '..');
const ARTIFACTS = process.env.BROWSER_ARTIFACTS_DIR ?? join(REPO, 'target', 'browser-artifacts');
const CHROMIUM_ARGS = [
  '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  // WebGL in software, for the 3D viewer.
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
];
const SEED_TIMEOUT_MS = 300_000;

/** The server under test, its API key and the seeded uploads (filled in `before`). */
const server = { child: null, dataDir: null, base: null, key: null, output: [] };
const seeded = {};
let browser = null;

before(async () => {
  await startServer();
  await seed();
  browser = await chromium.launch({
    executablePath: process.env.CHROMIUM_PATH ?? '/usr/bin/chromium',
    args: CHROMIUM_ARGS,
  });
}, { timeout: 420_000 });

after(async () => {
  await browser?.close();
  await stopServer();
}, { timeout: 30_000 });

test('overview shows stages, charts, tenant counts and the dead letter', { timeout: 120_000 }, async () => {
  await withPage('overview.png', { signedIn: false }, async (page) => {
    await page.goto(`${server.base}/ui/`);
    await page.locator('#api-key').fill(server.key);
    await page.locator('#login').click();
    await page.locator('#overview').waitFor();
    for (const stage of ['ingest', 'convert']) {
      await page.locator(`#stage-table tr[data-stage="${stage}"]`).waitFor({ state: 'visible' });
    }

    await eventually('tenant summary with succeeded ≥ 2 and dead ≥ 1', 15_000, async () => {
      const text = await page.locator('#tenant-summary').innerText();
      const succeeded = countIn(text, 'succeeded');
      const dead = countIn(text, 'dead');
      return succeeded >= 2 && dead >= 1 ? true : `tenant summary reads ${JSON.stringify(text)}`;
    });

    await page.locator('#chart-depth svg path[data-series]').first().waitFor({ state: 'attached' });
    assert.equal(await page.locator('#chart-depth svg path[data-series="ingest"]').count(), 1);
    assert.ok(await page.locator('#chart-throughput svg path[data-series]').count() >= 1);

    const row = page.locator(`#dead-table tr[data-job="${seeded.broken.job_id}"]`);
    await row.waitFor({ state: 'visible' });
    assert.match(await row.innerText(), /ingest/);
    const message = (await row.locator('.error-message').first().innerText()).trim();
    assert.ok(message.length > 0, 'the dead letter shows its error message');
    assert.equal(await row.locator(`button.retry[data-job="${seeded.broken.job_id}"]`).count(), 1);
  });
});

test('asset page shows the joints, the 3D view and the downloads', { timeout: 120_000 }, async () => {
  const { asset_id: assetId } = seeded.cabinet;
  const artifacts = await apiJson(`/v1/assets/${assetId}/artifacts`);
  const recordItem = artifacts.items.find((a) => a.name === 'record.json');
  assert.ok(recordItem, `record.json among ${artifacts.items.map((a) => a.path).join(', ')}`);
  const record = await apiJson(recordItem.href);
  assert.ok(record.joints.length > 0, 'the cabinet has joints');

  await withPage('asset.png', {}, async (page) => {
    await page.goto(`${server.base}/ui/#/assets/${assetId}`);
    await page.locator('#asset').waitFor();
    // The viewer settles either way; the joint table is checked before its verdict.
    await page.waitForSelector('#viewer[data-ready="true"], #viewer[data-error]', { timeout: 60_000 })
      .catch(() => {});

    const rows = page.locator('#joints tr[data-joint]');
    await rows.first().waitFor({ timeout: 30_000 });
    const names = await rows.evaluateAll((trs) => trs.map((tr) => tr.dataset.joint));
    assert.deepEqual([...names].sort(), record.joints.map((j) => j.name).sort());
    assert.equal(names.length, record.joints.length);

    const viewer = page.locator('#viewer');
    const error = await viewer.getAttribute('data-error');
    assert.equal(error, null, `the viewer failed: ${error}`);
    assert.equal(await viewer.getAttribute('data-ready'), 'true', 'the viewer is ready within 60 s');
    assert.equal(Number(await viewer.getAttribute('data-joints')), record.joints.length);
    assert.equal(Number(await viewer.getAttribute('data-parts')), record.parts.length);

    const canvas = page.locator('#viewer canvas');
    const box = await canvas.boundingBox();
    assert.ok(box && box.width > 0 && box.height > 0, `canvas box ${JSON.stringify(box)}`);
    const pixels = await canvas.evaluate(distinctColours);
    assert.ok(pixels.width > 0 && pixels.height > 0, `canvas size ${JSON.stringify(pixels)}`);
    assert.ok(pixels.distinct >= 8, `the canvas is not blank: ${pixels.distinct} distinct colours`);

    const preview = page.locator('#preview img');
    await preview.waitFor({ state: 'visible', timeout: 30_000 });
    const previewSize = await preview.evaluate((img) => ({ width: img.naturalWidth, height: img.naturalHeight }));
    assert.ok(previewSize.width > previewSize.height && previewSize.height > 0,
      `the rendered preview (four views side by side) loaded: ${JSON.stringify(previewSize)}`);

    const urdf = page.locator('#downloads a[data-path$="/model.urdf"]');
    assert.ok(await urdf.count() >= 1, 'a download link for model.urdf');
    assert.match(await urdf.first().innerText(), /model\.urdf/);
  });
});

test('retrying a dead letter requeues it', { timeout: 120_000 }, async () => {
  const { asset_id: assetId, job_id: jobId } = seeded.broken;
  const ingestAttempt = async () => (await apiJson(`/v1/assets/${assetId}`)).job.stages
    .find((s) => s.name === 'ingest').attempt;
  const attemptBefore = await ingestAttempt();

  await withPage('retry.png', {}, async (page) => {
    await page.goto(`${server.base}/ui/#/`);
    const button = page.locator(`button.retry[data-job="${jobId}"]`);
    await button.waitFor({ state: 'visible' });
    await button.click();
    await page.waitForFunction(
      (job) => document.querySelector(`#dead-table tr[data-job="${job}"]`)?.textContent.includes('requeued'),
      jobId, { timeout: 30_000 });
    assert.match(await page.locator(`#dead-table tr[data-job="${jobId}"]`).innerText(), /requeued: ingest/);

    await eventually('a retry event or a new ingest attempt', 30_000, async () => {
      const events = await apiJson(`/v1/jobs/${jobId}/events`);
      const kinds = events.items.map((e) => e.kind);
      const attempt = await ingestAttempt();
      return kinds.some((k) => k.includes('retr')) || attempt > attemptBefore
        ? true
        : `events ${kinds.join(', ')}; ingest attempt ${attempt} (was ${attemptBefore})`;
    });
  });
});

test('batch statistics show the seeded batch', { timeout: 120_000 }, async () => {
  const stats = await apiJson('/v1/batches/seed/stats');
  assert.equal(stats.converted, 2, `stats: ${JSON.stringify(stats)}`);

  await withPage('batch.png', {}, async (page) => {
    await page.goto(`${server.base}/ui/#/batches`);
    await page.locator('#batches tr[data-batch="seed"] a').click();
    await page.locator('#batch-stats').waitFor();
    await page.locator('#chart-categories svg rect.bar').first().waitFor();
    assert.ok(await page.locator('#chart-categories svg rect.bar').count() >= 1);
    for (const id of ['chart-materials', 'chart-joint-types', 'chart-mass', 'chart-size', 'chart-parts']) {
      assert.equal(await page.locator(`#${id} svg`).count(), 1, `#${id} has a chart`);
    }
    assert.equal((await page.locator('#batch-stats [data-field="converted"]').innerText()).trim(), '2');
    assert.equal(await page.locator('#download-batch-json').count(), 1);
  });
});

// ---- the server ------------------------------------------------------------------------------

async function startServer() {
  const bin = process.env.UNIPHYS_BIN;
  if (!bin) {
    throw new Error('UNIPHYS_BIN is not set: point it at the uniphys binary, e.g. UNIPHYS_BIN=$PWD/target/debug/uniphys');
  }
  server.dataDir = await mkdtemp(join(tmpdir(), 'uniphys-browser-'));
  const port = await freePort();
  const child = spawn(bin, ['serve', '--listen', `127.0.0.1:${port}`], {
    env: { ...process.env, UNIPHYS_DATA_DIR: server.dataDir, UNIPHYS_LOG: 'warn' },
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  server.child = child;
  const remember = (line) => {
    server.output.push(line);
    if (server.output.length > 200) server.output.shift();
  };
  createInterface({ input: child.stdout }).on('line', remember);
  const stderr = createInterface({ input: child.stderr });
  stderr.on('line', remember);
  server.base = await new Promise((resolveBase, reject) => {
    const fail = (why) => reject(new Error(`${why}; its last output:\n${server.output.join('\n')}`));
    const timer = setTimeout(() => fail(`${bin} serve printed no "API on http://" line within 60 s`), 60_000);
    stderr.on('line', (line) => {
      if (!line.startsWith('API on http://')) return;
      clearTimeout(timer);
      resolveBase(line.slice('API on '.length).trim());
    });
    child.once('error', (e) => {
      clearTimeout(timer);
      fail(`cannot start ${bin}: ${e.message}`);
    });
    child.once('exit', (code, signal) => {
      clearTimeout(timer);
      fail(`${bin} serve exited (${code ?? signal}) before listening`);
    });
  });
  server.key = (await readFile(join(server.dataDir, 'api-key'), 'utf8')).trim();
  assert.ok(server.key, 'the data directory has an API key');
}

async function stopServer() {
  const { child } = server;
  if (child && child.exitCode === null && child.signalCode === null) {
    const exited = once(child, 'exit');
    child.kill('SIGTERM');
    const timer = setTimeout(() => child.kill('SIGKILL'), 10_000);
    await exited;
    clearTimeout(timer);
  }
  if (server.dataDir) await rm(server.dataDir, { recursive: true, force: true });
}

/** A port free on 127.0.0.1 right now. */
async function freePort() {
  const probe = createServer();
  await new Promise((ok) => probe.listen(0, '127.0.0.1', ok));
  const { port } = probe.address();
  await new Promise((ok) => probe.close(ok));
  return port;
}

/** Uploads the two examples and a corrupt file in batch `seed`, then waits for their jobs. */
async function seed() {
  const examples = join(REPO, 'test_data', 'examples');
  const uploads = {
    cabinet: { file: 'cabinet.glb', body: await readFile(join(examples, 'cabinet.glb')), want: 'succeeded' },
    laptop: { file: 'laptop.glb', body: await readFile(join(examples, 'laptop.glb')), want: 'succeeded' },
    broken: { file: 'broken.glb', body: Buffer.from('this is not a glb file'), want: 'dead' },
  };
  for (const [name, upload] of Object.entries(uploads)) {
    const response = await api(`/v1/assets?filename=${encodeURIComponent(upload.file)}&batch=seed`, {
      method: 'POST',
      body: upload.body,
      headers: { 'content-type': 'application/octet-stream' },
    });
    const text = await response.text();
    assert.equal(response.status, 201, `upload of ${upload.file}: HTTP ${response.status} ${text}`);
    const { asset_id: assetId, job_id: jobId } = JSON.parse(text);
    seeded[name] = { ...upload, asset_id: assetId, job_id: jobId };
  }

  const started = Date.now();
  let lastReport = started;
  const pending = new Set(Object.keys(seeded));
  while (pending.size > 0) {
    const waiting = [];
    for (const name of [...pending]) {
      const { file, asset_id: assetId, want } = seeded[name];
      const { job } = await apiJson(`/v1/assets/${assetId}`);
      if (job.state === want) {
        pending.delete(name);
        continue;
      }
      const stages = job.stages.map((s) => `${s.name} ${s.state}`).join(', ');
      if (job.state !== 'running') {
        const errors = job.stages.flatMap((s) => s.errors.map((e) => `${s.name}: ${e.kind}: ${e.message}`));
        throw new Error(`${file} ended ${job.state}, not ${want} (${stages}) ${errors.join('; ')}`);
      }
      waiting.push(`${file} ${job.id}: ${stages}`);
    }
    if (pending.size === 0) break;
    if (Date.now() - started > SEED_TIMEOUT_MS) {
      throw new Error(`seeded jobs still not done after ${SEED_TIMEOUT_MS / 1000} s: ${waiting.join(' | ')}`);
    }
    if (Date.now() - lastReport > 15_000) {
      console.log(`waiting for ${waiting.join(' | ')}`);
      lastReport = Date.now();
    }
    await sleep(1000);
  }
}

// ---- helpers -------------------------------------------------------------------------------

/** `fetch` of `path` on the server with the API key. */
function api(path, init = {}) {
  return fetch(`${server.base}${path}`, {
    ...init,
    headers: { ...init.headers, authorization: `Bearer ${server.key}` },
  });
}

async function apiJson(path) {
  const response = await api(path);
  const text = await response.text();
  assert.ok(response.ok, `GET ${path}: HTTP ${response.status} ${text}`);
  return JSON.parse(text);
}

/**
 * Runs `body(page)` in a fresh browser context (signed in through localStorage unless
 * `signedIn` is false), then saves a full-page screenshot `name`, pass or fail.
 */
async function withPage(name, { signedIn = true }, body) {
  const context = await browser.newContext({ viewport: { width: 1280, height: 900 } });
  if (signedIn) {
    await context.addInitScript((key) => localStorage.setItem('uniphys.apiKey', key), server.key);
  }
  const page = await context.newPage();
  page.on('pageerror', (e) => console.log(`[${name}] page error: ${e.message}`));
  page.on('console', (m) => {
    if (m.type() === 'error') console.log(`[${name}] console: ${m.text()}`);
  });
  try {
    await body(page);
  } finally {
    await mkdir(ARTIFACTS, { recursive: true });
    await page.screenshot({ path: join(ARTIFACTS, name), fullPage: true })
      .catch((e) => console.log(`[${name}] no screenshot: ${e.message}`));
    await context.close();
  }
}

/** Retries `check` (true, or a string saying what it saw) until true or `timeoutMs` passes. */
async function eventually(what, timeoutMs, check) {
  const deadline = Date.now() + timeoutMs;
  let seen = '';
  for (;;) {
    const result = await check();
    if (result === true) return;
    seen = result;
    if (Date.now() > deadline) assert.fail(`${what} within ${timeoutMs / 1000} s; last seen: ${seen}`);
    await sleep(500);
  }
}

/** The number after `label` in the text (`succeeded\n2` → 2), or NaN. */
function countIn(text, label) {
  const match = new RegExp(`${label}\\D*?([\\d,]+)`, 'i').exec(text);
  return match ? Number(match[1].replace(/,/g, '')) : Number.NaN;
}

/** Runs in the page: how many distinct colours (5 bits a channel) the WebGL canvas shows. */
function distinctColours(canvas) {
  const copy = document.createElement('canvas');
  copy.width = canvas.width;
  copy.height = canvas.height;
  const context = copy.getContext('2d');
  context.drawImage(canvas, 0, 0);
  const { data } = context.getImageData(0, 0, copy.width, copy.height);
  const colours = new Set();
  for (let i = 0; i < data.length; i += 4) {
    colours.add(((data[i] >> 3) << 10) | ((data[i + 1] >> 3) << 5) | (data[i + 2] >> 3));
  }
  return { width: canvas.width, height: canvas.height, distinct: colours.size };
}

function sleep(ms) {
  return new Promise((ok) => setTimeout(ok, ms));
}
