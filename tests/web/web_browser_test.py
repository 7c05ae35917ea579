#!/usr/bin/env python3
"""Headless Chromium watches the simulated robot through mostar_web.

robot_server runs the simulator (corridor scene); mostar_web serves the page over HTTPS;
chromedriver drives headless Chromium to the page with an observer's token. Checks:
  1. frames arrive and are shown, and the HUD is live: its update counter, the frames shown and
     the link state read back from the page's DOM change between two readings;
  2. the AR overlay is drawn over the image: at the centroids of the wall triangles of the shown
     frame (vertices the server projected with the console's camera model), the screenshot's
     pixels move towards the wall colour compared with a screenshot with the overlay switched
     off (the robot stands still, so the image under it is the same);
  3. edge processing runs in mostar_web: a frame that carries its own pair's edge result with
     possible obstacles (the corridor's low box, under the laser's plane) is shown with a
     magenta dot where the server put each one;
  4. mostar_web counted the frames it wrote and refused nothing.
Skips (77) only when chromium or chromedriver is missing.

Usage: web_browser_test.py ROBOT_SERVER MOSTAR_WEB SOURCE_DIR [--screenshot PATH]
"""

import os
import shutil
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import webtest  # noqa: E402

def main():
    args = webtest.program_args(sys.argv, __doc__, browser=True)
    if isinstance(args, int):
        return args
    robot_server, mostar_web, source, screenshot_copy = args

    check = webtest.Checks()
    failures = check.failures

    programs = webtest.Programs(robot_server, mostar_web, source)
    driver = None
    try:
        driver = webtest.WebDriver(programs.work, window=(1120, 820))
        driver.get(programs.url("/#token=" + webtest.TOKEN))
        stats = lambda: driver.js("return window.mostar ? window.mostar.stats : null")  # noqa: E731
        first = webtest.wait_for("10 frames shown and 2 HUD updates",
                         lambda: (lambda s: s if s and s["framesShown"] >= 10 and s["hudReceived"] >= 2
                                  else None)(stats()), 40)
        check(first["badMessages"] == 0, "the page decoded every message (%d bad)" % first["badMessages"])
        # The simulated LMS200 needs a few seconds (baud switch) before its first scan.
        webtest.wait_for("scans: link 'ok' and walls in the shown frame",
                 lambda: driver.js("return document.getElementById('hud-link').textContent === 'ok'"
                                   " && window.mostar.wallCentroids(5).length > 0"), 40)
        hud = lambda: driver.js(  # noqa: E731
            "const t = (id) => document.getElementById(id).textContent;"
            "return {seq: t('hud-seq'), link: t('hud-link'), pilot: t('hud-pilot'),"
            " watchdog: t('hud-watchdog'), estop: t('hud-estop'), age: t('hud-frame-age'),"
            " video: t('hud-video'), shown: window.mostar.stats.framesShown};")
        h1 = hud()
        time.sleep(1.5)
        h2 = hud()
        print("HUD:", h2)
        check(int(h2["seq"]) > int(h1["seq"]), "the HUD updates (update %s -> %s)" % (h1["seq"], h2["seq"]))
        check(h2["shown"] > h1["shown"], "frames keep coming (%d -> %d shown)" % (h1["shown"], h2["shown"]))
        check(h2["link"] == "ok", "link state 'ok' (got %r)" % h2["link"])
        check(h2["estop"] in ("released", "ENGAGED") and h2["watchdog"] not in ("", "?"),
              "the robot's watchdog (%r) and e-stop (%r) are shown" % (h2["watchdog"], h2["estop"]))
        check(h2["age"].endswith(" ms"), "the frame age is shown (%r)" % h2["age"])

        # Keep a frame with NEP dots on the page (frozen) while reading it and taking the
        # screenshot.
        webtest.wait_for("a frame shown with its edge result's possible obstacles",
                 lambda: driver.js("if (window.mostar.obstacleDots().length === 0) return false;"
                                   " window.mostar.freeze(true); return true;"), 60)
        centroids = driver.js("return window.mostar.wallCentroids(80)")
        dots = driver.js("return window.mostar.obstacleDots()")
        check(len(centroids) >= 10, "the shown frame has wall triangles in the image (%d sampled)" % len(centroids))
        with_overlay = driver.screenshot_png()
        driver.js("window.mostar.freeze(false)")
        w, h, a = webtest.read_png(with_overlay)
        magenta = 0
        for d in dots:
            x, y = int(round(d["x"])), int(round(d["y"]))
            if any(r >= 200 and g <= 90 and b >= 200
                   for yy in range(max(0, y - 1), min(h, y + 2)) for xx in range(max(0, x - 1), min(w, x + 2))
                   for r, g, b in [a[yy][xx][:3]]):
                magenta += 1
        check(len(dots) >= 1 and magenta >= 0.7 * len(dots),
              "%d of %d NEP dots of the frame's edge result are magenta in the screenshot" % (magenta, len(dots)))
        driver.js("document.getElementById('overlay').click()")
        shown = driver.js("return window.mostar.stats.framesShown")
        webtest.wait_for("3 frames without overlay",
                 lambda: driver.js("return window.mostar.stats.framesShown") >= shown + 3, 20)
        without_overlay = driver.screenshot_png()
        path = os.path.join(programs.work, "web_observer.png")
        with open(path, "wb") as f:
            f.write(with_overlay)
        if screenshot_copy:
            shutil.copyfile(path, screenshot_copy)
            print("screenshot written to", screenshot_copy)

        _, _, b = webtest.read_png(without_overlay)
        towards = 0
        eligible = 0
        for c in centroids:
            x, y = int(c["x"]), int(c["y"])
            if not (0 <= x < w and 0 <= y < h):
                continue
            wall = c["rgba"][:3]
            pa, pb = a[y][x], b[y][x]
            shift = [pa[i] - pb[i] for i in range(3)]
            to_wall = [wall[i] - pb[i] for i in range(3)]
            dot = sum(shift[i] * to_wall[i] for i in range(3))
            norm = sum(v * v for v in to_wall) ** 0.5
            if norm < 30:
                continue  # the image there already has the wall's colour: nothing to tell
            eligible += 1
            # At least 15 % of the way to the wall colour (walls are drawn 20-50 % opaque).
            if dot / norm > 0.15 * norm:
                towards += 1
        share = towards / max(1, eligible)
        check(eligible >= 10 and share >= 0.7,
              "%d of %d wall centroids show the wall colour over the image" % (towards, eligible))

        s = programs.stats()
        print("mostar_web stats:", s)
        check(s["frames_written"] >= 10 and s["frames_composed"] >= 10, "mostar_web composed and wrote frames")
        check(s["frames_with_edges"] >= 1 and s["edge_failed"] == 0 and s["edge_undecodable"] == 0,
              "mostar_web ran edge processing on the pairs (%d frames with their result)" % s["frames_with_edges"])
        check(s["token_refused"] == 0 and s["bad_frames"] == 0 and s["tls_failures"] == 0,
              "nothing refused in a clean session")
    except Exception as e:  # noqa: BLE001 - report and fail, never hang
        failures.append(repr(e))
        print("FAIL:", repr(e))
    finally:
        if driver:
            driver.quit()
    return programs.finish(failures)


if __name__ == "__main__":
    sys.exit(main())
