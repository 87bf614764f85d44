// A planemap report opened as a person would: from disk (file://) in headless Chromium, with no
// server and no network. Fails unless the 3-D view draws the map (enough canvas pixels differ from
// the background) and the page's object table lists exactly map.json's objects (ids, classes,
// dimensions). Saves a screenshot of the 3-D view and its legend.
//   node check_report.mjs REPORT.html MAP.json SCREENSHOT.png
// Exit codes: 0 passed, 1 failed, 77 skipped (no Chromium, or web/node_modules not installed).
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const CHROMIUM = '/usr/bin/chromium';
const SKIP = 77;
const BACKGROUND = [0xf4, 0xf4, 0xf0];  // web/report.js's scene background
const MIN_DIFFERENCE = 48;              // per channel: above the grid's lines (40), below any drawn colour
const MIN_DRAWN_SHARE = 0.01;           // of the canvas's pixels

const [reportFile, mapFile, screenshotFile] = process.argv.slice(2);
if (!screenshotFile) {
  console.error('usage: node check_report.mjs REPORT.html MAP.json SCREENSHOT.png');
  process.exit(2);
}
if (!fs.existsSync(CHROMIUM)) {
  console.log(`skipped: ${CHROMIUM} is not installed (scripts/setup.sh --with-browser installs it)`);
  process.exit(SKIP);
}
let chromium;
try {
  ({ chromium } = await import(new URL('../../web/node_modules/playwright-core/index.mjs', import.meta.url)));
} catch {
  console.log('skipped: web/node_modules/playwright-core is not installed (scripts/setup.sh runs npm ci in web/)');
  process.exit(SKIP);
}

const failures = [];
const check = (ok, what) => { if (!ok) failures.push(what); };

// Chromium on a machine without network: no first-run, sync, update or QUIC probes, which would
// otherwise stall it; a fresh profile each run.
const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'planemap-chromium-'));
const browser = await chromium.launchPersistentContext(profile, {
  executablePath: CHROMIUM,
  headless: true,
  viewport: { width: 1280, height: 900 },
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
         '--disable-component-update', '--disable-sync'],
});
try {
  const page = await browser.newPage();
  page.on('pageerror', (e) => failures.push('page error: ' + e.message));
  page.on('console', (m) => { if (m.type() === 'error') failures.push('console error: ' + m.text()); });
  await page.goto('file://' + path.resolve(reportFile));
  await page.waitForSelector('#view[data-state="ready"], #view[data-state="error"]', { timeout: 60000 });
  const state = await page.getAttribute('#view', 'data-state');
  check(state === 'ready', '3-D view: ' + (await page.textContent('#view')));

  // 1. The canvas shows the map: its screenshot, decoded by the page itself, against the background.
  const canvas = page.locator('#view canvas');
  const png = (await canvas.screenshot()).toString('base64');
  const drawn = await page.evaluate(async ({ png, background, minDifference }) => {
    const image = new Image();
    image.src = 'data:image/png;base64,' + png;
    await image.decode();
    const context = Object.assign(document.createElement('canvas'), { width: image.width, height: image.height }).getContext('2d');
    context.drawImage(image, 0, 0);
    const pixels = context.getImageData(0, 0, image.width, image.height).data;
    let count = 0;
    for (let i = 0; i < pixels.length; i += 4) {
      if ([0, 1, 2].some((c) => Math.abs(pixels[i + c] - background[c]) > minDifference)) ++count;
    }
    return { count, total: pixels.length / 4 };
  }, { png, background: BACKGROUND, minDifference: MIN_DIFFERENCE });
  const share = drawn.count / drawn.total;
  console.log(`canvas: ${drawn.count} of ${drawn.total} pixels drawn (${(100 * share).toFixed(1)} %)`);
  check(share >= MIN_DRAWN_SHARE, `canvas nearly empty: ${(100 * share).toFixed(2)} % drawn, expected >= ${100 * MIN_DRAWN_SHARE} %`);

  // 2. The object table is map.json's objects: ids, classes, dimensions (shown to 0.1 cm).
  const map = JSON.parse(fs.readFileSync(mapFile, 'utf8'));
  const rows = await page.$$eval('#objects tr[data-object-id]', (trs) => trs.map((tr) => ({
    id: Number(tr.dataset.objectId), label: tr.dataset.class, dimensions: tr.dataset.dimensionsCm.split(' ').map(Number),
  })));
  console.log(`objects: ${rows.length} on the page, ${map.objects.length} in ${mapFile}`);
  check(rows.length === map.objects.length, `the page lists ${rows.length} objects, map.json has ${map.objects.length}`);
  for (const o of map.objects) {
    const row = rows.find((r) => r.id === o.id);
    if (!row) { failures.push(`object ${o.id} (${o.label}) is not on the page`); continue; }
    check(row.label === o.label, `object ${o.id}: class ${row.label} on the page, ${o.label} in map.json`);
    for (let k = 0; k < 3; ++k) {
      check(Math.abs(row.dimensions[k] - 100 * o.dimensions[k]) <= 0.051,
            `object ${o.id}: dimension ${k} ${row.dimensions[k]} cm on the page, ${(100 * o.dimensions[k]).toFixed(3)} cm in map.json`);
    }
  }
  // The 3-D view draws the same objects.
  const drawnIds = await page.evaluate(() => JSON.parse(document.getElementById('report-data').textContent).objects.map((o) => o.id));
  check(JSON.stringify(drawnIds) === JSON.stringify(map.objects.map((o) => o.id)), 'the 3-D view\'s objects differ from map.json\'s');

  // 3. A picture of the view and its legend.
  const clip = await page.evaluate(() => {  // in page coordinates, as a full-page screenshot's clip is
    const view = document.getElementById('view').getBoundingClientRect();
    const legend = document.getElementById('legend').getBoundingClientRect();
    return { x: view.x + window.scrollX, y: view.y + window.scrollY, width: view.width, height: legend.bottom - view.top };
  });
  await page.screenshot({ path: screenshotFile, fullPage: true, clip });
  console.log('wrote ' + screenshotFile);
} finally {
  await browser.close();
  fs.rmSync(profile, { recursive: true, force: true });
}

for (const f of failures) console.error('FAILED: ' + f);
console.log(failures.length ? `report check: ${failures.length} failures` : 'report check: passed');
process.exit(failures.length ? 1 : 0);
