// Load the Hydrolux page in Debian's chromium (headless, WebGPU on the CPU
// through SwiftShader), show each scene in turn, wait for frames, and
// record the image, the frame time, the adapter and every console error. Used by
// crates/hydrolux-web/tests/browser.rs. Two images per scene: the page's
// screenshot (what a person sees, through egui and the canvas) and the
// water image the page reads back from its own texture (`capture=N`).
// Headless chromium presents a WebGPU canvas only with Vulkan compositing
// on SwiftShader (the flags below); without them its GPU process crashes at
// the canvas and the device is lost.
//
//   node browser.mjs URL OUTDIR WIDTH HEIGHT SCENE...
// writes OUTDIR/SCENE.png (the page) and OUTDIR/SCENE.capture.png (its
// image) per scene, OUTDIR/report.json, and OUTDIR/no-webgpu.json: what
// the page says in a browser without WebGPU.
import { chromium } from "playwright-core";
import { writeFileSync } from "node:fs";
import { setTimeout as sleep } from "node:timers/promises";

const [url, outdir, width, height, ...scenes] = process.argv.slice(2);
const w = Number(width), h = Number(height);
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  args: [
    "--headless=new", "--no-sandbox", "--enable-unsafe-webgpu", "--use-webgpu-adapter=swiftshader",
    "--enable-features=Vulkan", "--use-vulkan=swiftshader", "--use-angle=swiftshader",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--no-first-run", "--disable-quic",
  ],
});
const report = [];
// One page for every scene, switched as the scene picker does: the page
// loads and compiles once.
const page = await browser.newPage({ viewport: { width: w, height: h }, deviceScaleFactor: 1 });
let errors = [];
page.on("console", (m) => { if (m.type() === "error") errors.push(m.text()); });
page.on("pageerror", (e) => errors.push(String(e)));
await page.goto(`${url}?scene=${scenes[0]}&time=0&paused=1&ui=0&width=${w}&height=${h}&capture=5`);
for (const [i, scene] of scenes.entries()) {
  const started = Date.now();
  if (i > 0) {
    errors = [];
    await page.evaluate((s) => window.hydrolux_show(s), scene);
  }
  try {
    // The scene's fifth frame read back, or an error reported by the page.
    await page.waitForFunction(
      (s) => window.hydrolux && (window.hydrolux.error || (window.hydrolux.scene === s && window.hydrolux.png)),
      scene, { timeout: 240000, polling: 250 });
  } catch (e) {
    errors.push(`timed out waiting for frames: ${e.message.split("\n")[0]}`);
  }
  // A few more frames for a steady frame time.
  await sleep(500);
  const state = await page.evaluate(() => {
    const s = Object.assign({}, window.hydrolux || {});
    delete s.png;
    return s;
  });
  const png = await page.evaluate(() => window.hydrolux && window.hydrolux.png ? Array.from(window.hydrolux.png) : null);
  if (png) writeFileSync(`${outdir}/${scene}.capture.png`, Buffer.from(png));
  await page.screenshot({ path: `${outdir}/${scene}.png`, clip: { x: 0, y: 0, width: w, height: h }, timeout: 120000 });
  report.push({ scene, state, errors, seconds: (Date.now() - started) / 1000 });
  console.log(`${scene}: ${JSON.stringify(state)} errors=${errors.length} ${((Date.now() - started) / 1000).toFixed(1)} s`);
  if (state.error) break;
}
// Then every scene runs, as a person leaves the page open: unpaused until
// its clock has advanced PLAY_SECONDS of simulated time at PLAY_SCALE× real
// time, with the pointer dragged across the view (on the pool: ripples, a
// pulled ball). Any console error fails the scene (the pool once crashed on
// its second frame: a blocking readback a browser cannot do). A frame on a
// software adapter takes over 0.1 s and steps at most 0.1 s × the scale, so
// 0.3 s at 1× is three frames or more of up to twelve 120 Hz clock steps
// each (0.9 s at 3× was as many frames of three times the steps: the same
// frames and code paths for three times the wait). The volumetric liquid's
// scenes (named in $LIQUID_SCENES) take about a second a liquid step on
// SwiftShader: they play PLAY_SECONDS_LIQUID at a quarter of real time,
// two frames or more of three clock steps.
const PLAY_SECONDS = 0.3, PLAY_SECONDS_LIQUID = 0.05, PLAY_SCALE = 1, PLAY_SCALE_LIQUID = 0.25;
const liquidScenes = new Set((process.env.LIQUID_SCENES || "").split(",").filter((s) => s));
for (const entry of report) {
  if (entry.state.error) break;
  const scene = entry.scene;
  const started = Date.now();
  errors = [];
  await page.evaluate((s) => window.hydrolux_show(s), scene);
  await page.waitForFunction((s) => window.hydrolux.scene === s, scene, { timeout: 240000, polling: 100 });
  const startTime = await page.evaluate(() => window.hydrolux.time);
  const liquid = liquidScenes.has(scene);
  const wanted = liquid ? PLAY_SECONDS_LIQUID : PLAY_SECONDS;
  await page.evaluate((k) => window.hydrolux_play(k), liquid ? PLAY_SCALE_LIQUID : PLAY_SCALE);
  let played = null;
  try {
    // Drag across the middle of the view while it runs: four input events,
    // as each waits for the page to take it, i.e. for a frame (over a
    // second on SwiftShader; eight moves made the drag the run's longest part).
    await page.mouse.move(w * 0.45, h * 0.6);
    await page.mouse.down();
    await page.mouse.move(w * 0.65, h * 0.72);
    await page.mouse.up();
    await page.waitForFunction(
      (t) => window.hydrolux && (window.hydrolux.error || window.hydrolux.time >= t),
      startTime + wanted, { timeout: 300000, polling: 250 });
  } catch (e) {
    errors.push(`timed out running: ${e.message.split("\n")[0]}`);
  }
  played = await page.evaluate(() => ({ time: window.hydrolux.time, frames: window.hydrolux.scene_frames, error: window.hydrolux.error }));
  await page.evaluate(() => window.hydrolux_play(0));
  entry.played = { ...played, advanced: played.time - startTime, wanted, errors, seconds: (Date.now() - started) / 1000 };
  console.log(`${scene} running: ${JSON.stringify(entry.played)}`);
  if (played.error) break;
}
// A scene's TOML dropped onto the page opens as the picker's scenes do:
// its name on the page, its frames drawn, no console error.
{
  const started = Date.now();
  errors = [];
  const toml = [
    'description = "a calm sea, dropped onto the page"',
    "[camera]", "position = [0.0, 3.0, 0.0]", "look_at = [10.0, 1.0, -50.0]",
    "[water]", 'model = "sines"',
    "[sines]", "count = 8",
  ].join("\n");
  const transfer = await page.evaluateHandle((text) => {
    const d = new DataTransfer();
    d.items.add(new File([text], "dropped-calm.toml", { type: "application/toml" }));
    return d;
  }, toml);
  await page.dispatchEvent("canvas", "drop", { dataTransfer: transfer });
  let shown = false;
  try {
    await page.waitForFunction(
      () => window.hydrolux && (window.hydrolux.error || (window.hydrolux.scene === "dropped-calm.toml" && window.hydrolux.png)),
      null, { timeout: 240000, polling: 250 });
    shown = await page.evaluate(() => window.hydrolux.scene === "dropped-calm.toml" && !!window.hydrolux.png);
  } catch (e) {
    errors.push(`timed out waiting for the dropped scene: ${e.message.split("\n")[0]}`);
  }
  const dropped = { shown, errors, seconds: (Date.now() - started) / 1000 };
  writeFileSync(`${outdir}/dropped.json`, JSON.stringify(dropped));
  console.log(`dropped scene: ${JSON.stringify(dropped)}`);
}
await browser.close();
writeFileSync(`${outdir}/report.json`, JSON.stringify(report, null, 1));

// A browser without WebGPU: the page must say why it cannot run.
const plain = await chromium.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  args: ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-webgpu",
         "--disable-background-networking", "--disable-component-update", "--no-first-run"],
});
const plainPage = await plain.newPage({ viewport: { width: w, height: h } });
await plainPage.goto(`${url}?scene=${scenes[0]}&ui=0`);
let said = "";
try {
  await plainPage.waitForFunction(() => window.hydrolux && window.hydrolux.error, null, { timeout: 120000 });
} catch (e) { said = "(no error reported) "; }
said += await plainPage.evaluate(() => document.getElementById("status").textContent);
const gpu = await plainPage.evaluate(() => !!navigator.gpu);
writeFileSync(`${outdir}/no-webgpu.json`, JSON.stringify({ status: said, navigator_gpu: gpu }));
console.log(`without WebGPU (navigator.gpu ${gpu}): ${said}`);
await plain.close();
