#!/usr/bin/env python3
"""`mrr explore`'s page in a real browser: headless Chromium driven by Selenium.
Loads the page; changes tau_n and sees stencil L0's shaded count change; turns the motion knob
(pan) and sees the motion layer come and go; clicks a pixel and reads its probe; switches the
probe to the port and sees the same pixel; turns noise-aware on and reads the pixel's stochastic
stages against the oracle's seeds; walks the step-through; no console errors. Takes a screenshot
(MRR_EXPLORE_SCREENSHOT=path; "" skips).

    test_explore_browser.py path/to/mrr
Exit 77 (ctest: skipped) without selenium or chromedriver, unless MRR_REQUIRE_GL=1 (CI), where
that fails; without an EGL device the port's steps are skipped unless MRR_REQUIRE_GL=1."""
import os
import shutil
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from explore_server import ExploreServer, port_required  # noqa: E402

MRR = sys.argv[1] if len(sys.argv) > 1 else "build/mrr"
SHOT = os.environ.get("MRR_EXPLORE_SCREENSHOT", "")
SCENE = os.environ.get("MRR_EXPLORE_SCENE", "builtin:demo")
TOOL = "test_explore_browser"


def skip(why):
    if port_required():
        fail(why + " (MRR_REQUIRE_GL=1: required)")
    print(f"{TOOL}: SKIP: {why}", file=sys.stderr)
    sys.exit(77)


def fail(why):
    print(f"{TOOL}: FAIL: {why}", file=sys.stderr)
    sys.exit(1)


try:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import Select, WebDriverWait
except ImportError as e:
    skip(f"selenium is missing ({e}); apt-get install python3-selenium")

driver_path = shutil.which("chromedriver") or "/usr/bin/chromedriver"
browser = shutil.which("chromium") or shutil.which("chromium-browser")
if not os.path.exists(driver_path) or not browser:
    skip("chromedriver or chromium is missing; apt-get install chromium chromium-driver")


def main():
    server = ExploreServer(MRR, "--scene", SCENE, "--threads", "2")
    options = webdriver.ChromeOptions()
    options.binary_location = browser
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--hide-scrollbars", "--window-size=1560,1240", "--force-device-scale-factor=1"):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = None
    try:
        driver = webdriver.Chrome(service=Service(driver_path), options=options)
        run(driver, server)
    finally:
        if driver:
            driver.quit()
        alive = server.alive()
        server.stop()
        if not alive:
            fail("the server died:\n" + "".join(server.stderr_lines))


def run(d, server):
    wait = WebDriverWait(d, 60, poll_frequency=0.1)
    by_id = lambda i: d.find_element(By.ID, i)  # noqa: E731
    body = lambda: d.find_element(By.TAG_NAME, "body")  # noqa: E731

    def rendered(count):
        wait.until(lambda _: body().get_attribute("data-state") == "ready"
                   and int(body().get_attribute("data-renders")) >= count and body().get_attribute("data-busy") == "0")

    # 1. The page loads and renders its first frame.
    d.get(server.url)
    rendered(1)
    port = body().get_attribute("data-port") == "available"
    if not port and port_required():
        fail("the page says the port is unavailable, with MRR_REQUIRE_GL=1")
    print(f"{TOOL}: page loaded; port {'available' if port else 'unavailable'}", file=sys.stderr)

    # 2. Stencil L0: change tau_n and see its shaded count change.
    Select(by_id("layer")).select_by_value("stencil.L0")
    wait.until(lambda _: "ones" in d.find_element(By.CSS_SELECTOR, "#panel-cpu .legend").text
               and body().get_attribute("data-busy") == "0")
    before = by_id("shaded-L0").text
    legend_before = d.find_element(By.CSS_SELECTOR, "#panel-cpu .legend").text
    tau = by_id("tau_n")
    renders = int(body().get_attribute("data-renders"))
    tau.send_keys(Keys.CONTROL, "a")  # select what is there and type over it, as a user does
    tau.send_keys("1.5", Keys.TAB)
    rendered(renders + 1)
    wait.until(lambda _: by_id("shaded-L0").text != before)
    after = by_id("shaded-L0").text
    legend_after = d.find_element(By.CSS_SELECTOR, "#panel-cpu .legend").text
    if legend_after == legend_before:
        fail(f"stencil L0's legend did not change with tau_n: {legend_after!r}")
    print(f"{TOOL}: tau_n 0.1 -> 1.5: stencil L0 shades {before} -> {after}", file=sys.stderr)

    # 2b. The motion knob (--pan): a pan renders the motion term; 0 takes it away.
    def layers():
        return [o.get_attribute("value") for o in Select(by_id("layer")).options]
    if "motion" in layers():
        fail("a still frame offers the motion layer")
    pan = by_id("pan")
    for value, expect in (("0.3", True), ("0", False)):
        renders = int(body().get_attribute("data-renders"))
        pan.send_keys(Keys.CONTROL, "a")
        pan.send_keys(value, Keys.TAB)
        rendered(renders + 1)
        wait.until(lambda _: ("motion" in layers() and "levellimit" in layers()) == expect)
    print(f"{TOOL}: pan 0.3 -> the motion and levellimit layers; pan 0 -> gone", file=sys.stderr)
    Select(by_id("layer")).select_by_value("stencil.L0")

    # 3. Click a pixel and read its probe (both paths when the port is here).
    view = d.find_element(By.CSS_SELECTOR, "#panel-cpu .view")
    ActionChains(d).move_to_element(view).click().perform()  # the centre: pixel (160, 90) at 320x180
    wait.until(lambda _: by_id("probe-section").get_attribute("data-pixel") and body().get_attribute("data-busy") == "0")
    pixel = by_id("probe-section").get_attribute("data-pixel")
    rows = d.find_elements(By.CSS_SELECTOR, "#probe tbody tr:not(.probe-section)")  # values, not step headings
    if len(rows) < 20:
        fail(f"the probe of {pixel} has {len(rows)} rows")
    headings = [h.text for h in d.find_elements(By.CSS_SELECTOR, "#probe tbody tr.probe-section")]
    if port and not any("(gbuffer.frag)" in h for h in headings):
        fail(f"the two-path probe is not grouped by step under its shader: {headings[:3]}")
    keys = [r.find_element(By.TAG_NAME, "td").text for r in rows]
    if not any(k.startswith("gbuffer") for k in keys) or "final" not in keys:
        fail(f"the probe does not run from the G-buffer to the final value: {keys[:5]} ... {keys[-3:]}")
    print(f"{TOOL}: probe of pixel {pixel}: {len(rows)} rows, {by_id('probe-verdict').text or 'one path'}",
          file=sys.stderr)
    if not d.find_elements(By.CSS_SELECTOR, "#panel-cpu svg .pixel"):
        fail("no footprint drawn for the probed pixel")

    # 4. Switch the probe to the port and see the same pixel.
    if port:
        Select(by_id("probe-path")).select_by_value("gpu")
        wait.until(lambda _: by_id("probe-section").get_attribute("data-path") == "gpu"
                   and body().get_attribute("data-busy") == "0")
        if by_id("probe-section").get_attribute("data-pixel") != pixel or by_id("probe-pixel").text != pixel:
            fail(f"the port's probe is of {by_id('probe-pixel').text}, not {pixel}")
        if "port" not in by_id("probe-source").text:
            fail(f"the probe does not say it is the port's: {by_id('probe-source').text!r}")
        port_rows = {r.find_elements(By.TAG_NAME, "td")[0].text: r.find_elements(By.TAG_NAME, "td")[1].text
                     for r in d.find_elements(By.CSS_SELECTOR, "#probe tbody tr")}
        if port_rows.get("pixel") != "(" + pixel.replace(",", ", ") + ")":
            fail(f"the port's probe row 'pixel' is {port_rows.get('pixel')!r}, not {pixel}")
        print(f"{TOOL}: the port's probe of the same pixel {pixel}: final {port_rows.get('final')}", file=sys.stderr)
        Select(by_id("probe-path")).select_by_value("both")
        wait.until(lambda _: by_id("probe-section").get_attribute("data-path") == "both"
                   and body().get_attribute("data-busy") == "0")
    elif port_required():
        fail("no port")
    else:
        print(f"{TOOL}: SKIP the port's steps: no EGL device here", file=sys.stderr)

    # 4b. Noise-aware: the probed pixel's stochastic stages against the oracle's seeds,
    # their mean, the accepted interval and where the value falls; off again, the table hides.
    by_id("probe-noise").click()
    wait.until(lambda _: by_id("noise-section").get_attribute("data-pixel") == pixel
               and body().get_attribute("data-busy") == "0")
    noise_rows = d.find_elements(By.CSS_SELECTOR, "#noise tbody tr")
    stages = {r.get_attribute("data-stage"): r.text for r in noise_rows if r.get_attribute("data-stage")}
    if "final" not in stages or not any(k.startswith("raw.L") for k in stages):
        fail(f"the noise-aware table lacks the stochastic stages: {sorted(stages)} ({by_id('noise-note').text!r})")
    if not all(" inside (" in t or " OUTSIDE (" in t for t in stages.values()):
        fail(f"a noise-aware row does not say where its value falls: {stages}")
    if "16 frames with independent seeds" not in by_id("noise-note").text or not by_id("noise-verdict").text:
        fail(f"the noise-aware panel does not say what it shows: {by_id('noise-note').text!r}")
    print(f"{TOOL}: noise-aware at {pixel}: {len(stages)} shaded stochastic stages; {by_id('noise-verdict').text[:60]}",
          file=sys.stderr)
    by_id("probe-noise").click()
    wait.until(lambda _: not by_id("noise-section").is_displayed() and body().get_attribute("data-busy") == "0")

    # 5. The step-through walks the stages with their text.
    by_id("teach").click()
    seen = []
    for _ in range(4):
        wait.until(lambda _: by_id("teach-text").text.strip() and body().get_attribute("data-busy") == "0")
        seen.append(by_id("teach-panel").get_attribute("data-part"))
        by_id("teach-next").click()
    if seen[0] != "gbuffer" or len(set(seen)) < 3:
        fail(f"the step-through showed {seen}")
    by_id("teach-close").click()
    print(f"{TOOL}: step-through: {' -> '.join(seen)} ...", file=sys.stderr)

    # 6. No console errors; the screenshot (the level map with the probed pixel's taps).
    errors = [e for e in d.get_log("browser") if e.get("level") == "SEVERE"]
    if errors:
        fail("console errors: " + "; ".join(e["message"][:200] for e in errors))
    if SHOT:  # the method's own stages: never-slower off (a small frame may fall back to full), tau_n back
        renders = int(body().get_attribute("data-renders"))
        if by_id("never_slower").is_selected():
            by_id("never_slower").click()
            rendered(renders + 1)
            renders += 1
        tau = by_id("tau_n")
        tau.send_keys(Keys.CONTROL, "a")
        tau.send_keys("0.1", Keys.TAB)
        rendered(renders + 1)
        Select(by_id("layer")).select_by_value(os.environ.get("MRR_EXPLORE_SHOT_LAYER", "alpha.L2"))
        wait.until(lambda _: body().get_attribute("data-busy") == "0")
        ActionChains(d).move_to_element_with_offset(view, 40, 20).perform()
        time.sleep(0.5)
        d.save_screenshot(SHOT)
        print(f"{TOOL}: screenshot {SHOT}", file=sys.stderr)
    # 7. Without the port (an EGL device that does not exist) the page works on the oracle and says so.
    alone = ExploreServer(MRR, "--scene", "builtin:demo", "--gl-device", "99")
    try:
        d.get(alone.url)
        wait.until(lambda _: body().get_attribute("data-state") == "ready" and body().get_attribute("data-busy") == "0")
        if body().get_attribute("data-port") != "unavailable" or "unavailable" not in by_id("port-name").text:
            fail(f"the page does not say the port is unavailable: {by_id('port-name').text!r}")
        ActionChains(d).move_to_element(d.find_element(By.CSS_SELECTOR, "#panel-cpu .view")).click().perform()
        wait.until(lambda _: by_id("probe-section").get_attribute("data-path") == "cpu"
                   and body().get_attribute("data-busy") == "0")
        if len(d.find_elements(By.CSS_SELECTOR, "#probe tbody tr")) < 20:
            fail("no oracle probe on the page without the port")
        errors = [e for e in d.get_log("browser") if e.get("level") == "SEVERE"]
        if errors:
            fail("console errors without the port: " + "; ".join(e["message"][:200] for e in errors))
        print(f"{TOOL}: without the port: the oracle alone, the port said unavailable", file=sys.stderr)
    finally:
        alone.stop()
    print(f"{TOOL}: OK", file=sys.stderr)


if __name__ == "__main__":
    main()
