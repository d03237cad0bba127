#!/usr/bin/env node
// Development aid: opens the display in headless Chromium (Debian's
// /usr/bin/chromium through puppeteer-core) and saves a PNG of the mission
// overview and of each ready-made view, printing the page's console errors.
// Not a test (the test is unit_test/ground/mission_control/web/display_test.mjs).
//
//   node ground/mission_control/web/dev/screenshots.mjs http://127.0.0.1:8091/ build/mission_control/screens [keys...]

import fs from 'node:fs';
import path from 'node:path';
import puppeteer from 'puppeteer-core';

const [base = 'http://127.0.0.1:8091/', outDir = 'build/mission_control/screens', ...keys] = process.argv.slice(2);
const views = keys.length
  ? keys
  : ['overview', 'map', 'drive-health', 'mission-state', 'event-log', 'plot.position', 'plot.heading', 'plot.speed', 'plot.drive-currents', 'plot.motor-temperatures', 'plot.battery', 'plot.task-cpu', 'tasks', 'packet.DRIVES'];
fs.mkdirSync(outDir, { recursive: true });

const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-dev-shm-usage'],
  defaultViewport: { width: 1920, height: 1080 }
});
try {
  const page = await browser.newPage();
  page.on('console', (m) => {
    if (['error', 'warn'].includes(m.type())) console.log(`[page ${m.type()}] ${m.text()}`);
  });
  page.on('pageerror', (e) => console.log(`[page exception] ${e.message}`));
  for (const key of views) {
    await page.goto(new URL(`#/browse/rse:root/rse:${key}`, base).href, { waitUntil: 'load' });
    await page.reload({ waitUntil: 'load' });
    await new Promise((r) => setTimeout(r, Number(process.env.WAIT_MS || 6000)));
    const file = path.join(outDir, `${key.replace(/[^A-Za-z0-9_.-]/g, '_')}.png`);
    await page.screenshot({ path: file });
    console.log(`saved ${file}`);
  }
} finally {
  await browser.close();
}
