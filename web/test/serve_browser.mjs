// Drives softface serve's page in headless Chromium (Debian's, through
// playwright-core): load it, move sliders, wait for each redrawn face, send
// bad requests, take a screenshot. Prints one JSON line with the figures;
// exits 1 if the page fails any check.
//
//   node serve_browser.mjs URL SCREENSHOT.png [MOVES]
import { chromium } from "playwright-core";

const [url, screenshot, movesText = "20"] = process.argv.slice(2);
const moves = Number(movesText);
const failures = [];
const check = (ok, what) => { if (!ok) failures.push(what); };

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  args: ["--no-sandbox", "--enable-unsafe-swiftshader", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"],
});
try {
  const page = await browser.newPage({ viewport: { width: 1100, height: 700 } });
  const pageErrors = [];
  page.on("pageerror", (e) => pageErrors.push(String(e)));
  await page.goto(url);
  // The page asks for the plan at rest as soon as its socket opens.
  await page.waitForFunction(() => window.softface && window.softface.replans >= 1,
                             null, { timeout: 60000 });
  const scene = await page.evaluate(() => fetch("/scene.json").then((r) => r.json()));
  const segment = scene.segments[0].name;

  // Move the first segment's sliders one step at a time, each time waiting
  // for the face drawn with that plan: the page's own slider-to-frame time.
  const setSlider = (k, value) => page.evaluate(([segment, k, value]) => {
    const input = document.querySelector(`input[data-segment="${segment}"][data-k="${k}"]`);
    input.value = value;
    input.dispatchEvent(new Event("input"));
    return window.softface.nextId - 1;
  }, [segment, k, value]);
  const waitFor = (id) => page.waitForFunction((id) => window.softface.lastId >= id, id,
                                               { timeout: 30000 });
  for (let i = 1; i <= moves; ++i) {
    const id = await setSlider(i % 2 ? 2 : 4, (6 * i) / moves);
    await waitFor(id);
  }
  const state = await page.evaluate(() => ({
    latencies: window.softface.latencies.slice(1), lastMax: window.softface.lastMax,
    drawMs: window.softface.drawMs, updateMs: window.softface.updateMs,
    answerMs: window.softface.answerMs,
    errors: window.softface.errors.slice() }));
  check(state.latencies.length >= moves, `${moves} re-plans drawn (got ${state.latencies.length})`);
  check(state.lastMax > 0.5, `the face moved (largest |u| ${state.lastMax} mm)`);
  check(state.errors.length === 0, `no error answers (${state.errors.join("; ")})`);

  // Bad requests get an error answer, and the server serves on.
  const answers = await page.evaluate(async (segment) => {
    const socket = new WebSocket(`ws://${location.host}/replan`);
    await new Promise((resolve) => (socket.onopen = resolve));
    const ask = (text) => new Promise((resolve) => {
      socket.onmessage = (e) => resolve(typeof e.data === "string" ? e.data : "binary");
      socket.send(text);
    });
    const result = [];
    result.push(await ask(JSON.stringify({ id: 1, motions: { nobody: [0, 0, 0, 0, 0, 0] } })));
    result.push(await ask(`{"id": 2, "motions": {"${segment}": [NaN, 0, 0, 0, 0, 0]}}`));
    result.push(await ask(JSON.stringify({ id: 3, motions: { [segment]: ["x", 0, 0, 0, 0, 0] } })));
    result.push(await ask(JSON.stringify({ id: 4, motions: { [segment]: [1e6, 0, 0, 0, 0, 0] } })));
    result.push(await ask(JSON.stringify({ id: 5, model: "no such model" })));
    result.push(await ask(JSON.stringify({ id: 6, motions: { [segment]: [1, 2] } })));
    result.push(await ask("not json"));
    result.push(await ask(JSON.stringify({ id: 7, motions: { [segment]: [0, 0, 1, 0, 0, 5] } })));
    socket.close();
    return result;
  }, segment);
  for (let i = 0; i < 7; ++i)
    check(answers[i].includes("\"error\""), `bad request ${i + 1} answered with an error (${answers[i]})`);
  check(answers[7] === "binary", "a good request after the bad ones is answered");
  const sceneAgain = await page.evaluate(() => fetch("/scene.json").then((r) => r.status));
  check(sceneAgain === 200, "the server serves after bad requests");
  check(pageErrors.length === 0, `no errors in the page (${pageErrors.join("; ")})`);

  // The pre / predicted / post-operative switch.
  const shows = [];
  for (const show of scene.post_operative ? ["pre", "post", "predicted"] : ["pre", "predicted"]) {
    await page.check(`input[name=show][value=${show}]`);
    shows.push(await page.evaluate(() => window.softface.showing));
  }
  check(shows.join() === (scene.post_operative ? "pre,post,predicted" : "pre,predicted"),
        `the view switches (${shows.join()})`);

  // Colour by the distance to the post-operative skin: the server measures
  // every re-plan.
  if (scene.post_operative) {
    const before = await page.evaluate(() => window.softface.lastId);
    await page.check("input[name=colour][value=distance]");
    await waitFor(before + 1);
    check(await page.evaluate(() => window.softface.colouredBy) === "distance",
          "the face is coloured by the distance to the post-operative skin");
  }

  await page.screenshot({ path: screenshot });
  const sorted = state.latencies.slice().sort((a, b) => a - b);
  const median = sorted.length ? sorted[Math.floor(sorted.length / 2)] : NaN;
  console.log(JSON.stringify({ replans: state.latencies.length, median_latency_ms: median,
                               max_latency_ms: sorted[sorted.length - 1],
                               last_answer_ms: state.answerMs, last_update_ms: state.updateMs, last_draw_ms: state.drawMs,
                               largest_displacement_mm: state.lastMax, bad_request_answers: answers.slice(0, 7),
                               failures }));
} finally {
  await browser.close();
}
process.exit(failures.length ? 1 : 0);
