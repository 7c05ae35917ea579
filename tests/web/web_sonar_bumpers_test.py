#!/usr/bin/env python3
"""Headless Chromium shows the sonar sectors, the edge results and the bumpers mostar_web sends.

1. The glass door scene (deploy/scenes/glass_door.pbtxt): the laser sees through the closed
   glass door, the sonar belt hears it. The shown frame carries sonar sectors (echoes, and at
   least one not seen by the laser); at the midpoints of the unseen sectors' outlines (vertices
   the server projected with the console's camera model) the screenshot is magenta; the map has
   the sonar fans; the HUD names the echoes and shows the bumper belt clear. Edge processing
   runs (the configuration's vision_enabled): frames carry their pair's edge result, and every
   magenta NEP dot the frame holds is drawn magenta.
2. The same room with the robot started with its rear 5 mm from the back wall: the simulated
   bumpers touch, the robot latches the stop, and the HUD shows the hit segment and the banner.
Skips (77) only when chromium or chromedriver is missing.

Usage: web_sonar_bumpers_test.py ROBOT_SERVER MOSTAR_WEB SOURCE_DIR [--screenshot PATH]
"""

import os
import re
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import webtest  # noqa: E402

def magenta_near(pixels, w, h, x, y, radius=2):
    """True when a pixel within `radius` of (x, y) is magenta (the outline colour, blended a
    little by the line's edges)."""
    for yy in range(max(0, y - radius), min(h, y + radius + 1)):
        for xx in range(max(0, x - radius), min(w, x + radius + 1)):
            r, g, b = pixels[yy][xx][:3]
            if r >= 200 and g <= 90 and b >= 200:
                return True
    return False


def text(driver, element_id):
    return driver.js("return document.getElementById(arguments[0]).textContent", element_id)


def scene_with_start(source, work, start):
    """The glass door scene with the robot's start pose replaced."""
    with open(os.path.join(source, "deploy/scenes/glass_door.pbtxt")) as f:
        scene = f.read()
    scene, n = re.subn(r"(?m)^start \{[^}]*\}", "start { %s }" % start, scene)
    assert n == 1, "the scene's start pose"
    path = os.path.join(work, "glass_door_bumped.pbtxt")
    with open(path, "w") as f:
        f.write(scene)
    return path


def main():
    args = webtest.program_args(sys.argv, __doc__, browser=True)
    if isinstance(args, int):
        return args
    robot_server, mostar_web, source, screenshot_copy = args

    check = webtest.Checks()
    failures = check.failures

    # 1. The glass door.
    programs = webtest.Programs(robot_server, mostar_web, source, server_args=[
        "--sim", os.path.join(source, "deploy/scenes/glass_door.pbtxt")])
    driver = None
    try:
        driver = webtest.WebDriver(programs.work, window=(1120, 820))
        driver.get(programs.url("/#token=" + webtest.TOKEN))
        # The simulated LMS200 needs a few seconds (baud switch) before its first scan; the belt
        # compares with the laser only after a scan.
        info = webtest.wait_for(
            "a frame with sonar sectors the laser does not see, outlined in the image",
            lambda: (lambda f: f if f and f["sonar"] and f["sonarUnseen"] >= 1
                     and driver.js("return window.mostar.sonarOutlineMidpoints().length") > 0
                     else None)(driver.js("return window.mostar.lastFrameInfo()")), 60)
        print("frame:", info)
        check(info["sonarEchoes"] >= 3, "the belt hears the room (%d echoes)" % info["sonarEchoes"])
        # Edge processing: some frames carry their own pair's result.
        webtest.wait_for("frames with their edge result",
                 lambda: driver.js("return window.mostar.stats.framesWithEdges") >= 3, 60)
        check(True, "frames carry their pair's edge result")
        webtest.wait_for("the bumper state in the HUD",
                 lambda: text(driver, "hud-bumpers") not in ("?", ""), 20)
        # The page keeps the frame it shows (frozen) while the test reads it and takes the
        # screenshot.
        webtest.wait_for("a frame shown with an outlined sonar sector",
                 lambda: driver.js("if (window.mostar.sonarOutlineMidpoints().length === 0) return false;"
                                   " window.mostar.freeze(true); return true;"), 30)
        midpoints = driver.js("return window.mostar.sonarOutlineMidpoints()")
        dots = driver.js("return window.mostar.obstacleDots()")
        png = driver.screenshot_png()
        driver.js("window.mostar.freeze(false)")
        w, h, pixels = webtest.read_png(png)
        hits = sum(1 for p in midpoints
                   if magenta_near(pixels, w, h, int(round(p["x"])), int(round(p["y"]))))
        check(len(midpoints) >= 2 and hits >= 0.7 * len(midpoints),
              "%d of %d sonar outline midpoints are magenta in the screenshot" % (hits, len(midpoints)))
        dot_hits = sum(1 for p in dots
                       if magenta_near(pixels, w, h, int(round(p["x"])), int(round(p["y"]))))
        print("NEP dots in the shown frame: %d, %d drawn magenta" % (len(dots), dot_hits))
        check(dot_hits >= 0.7 * len(dots), "the NEP dots are drawn magenta")
        sonar_cell = text(driver, "hud-sonar")
        bumpers_cell = text(driver, "hud-bumpers")
        print("HUD sonar: %r, bumpers: %r, edges: %r" % (sonar_cell, bumpers_cell, text(driver, "hud-edges")))
        check("echoes" in sonar_cell and "not seen by the laser" in sonar_cell,
              "the HUD names the sonar echoes the laser does not see")
        check(re.fullmatch(r"\d+ clear", bumpers_cell) is not None, "the HUD shows the bumper belt clear")
        # The map: sonar fans drawn (pixels other than black and the range rings' grey).
        map_colours = driver.js(
            "const c = document.getElementById('map');"
            "const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;"
            "let n = 0; for (let i = 0; i < d.length; i += 4) {"
            " if (Math.max(d[i], d[i + 1], d[i + 2]) - Math.min(d[i], d[i + 1], d[i + 2]) > 40) ++n; }"
            "return n;")
        check(map_colours > 300, "the map shows coloured sonar fans and points (%d pixels)" % map_colours)
        path = os.path.join(programs.work, "web_sonar_glass_door.png")
        with open(path, "wb") as f:
            f.write(png)
        if screenshot_copy:
            shutil.copyfile(path, screenshot_copy)
            print("screenshot written to", screenshot_copy)
        s = programs.stats()
        print("mostar_web stats:", s)
        check(s["frames_with_edges"] >= 1 and s["edge_results"] >= 1, "mostar_web ran edge processing")
        check(s["token_refused"] == 0 and s["bad_frames"] == 0, "nothing refused")
    except Exception as e:  # noqa: BLE001 - report and fail, never hang
        failures.append(repr(e))
        print("FAIL:", repr(e))
    finally:
        if driver:
            driver.quit()
            driver = None
    status = programs.finish(failures)
    if status != 0:
        return status

    # 2. The robot's rear 5 mm from the back wall (x = -4; the footprint reaches 0.56 m behind
    # the laser; the simulator refuses a start inside an obstacle), within the switches' 1 cm
    # contact margin: the rear bumper touches.
    scene_dir = tempfile.mkdtemp(prefix="mostar_web_scene_")
    scene = scene_with_start(source, scene_dir, "x_m: -3.435 y_m: 0.0 theta_rad: 0.0")
    programs = webtest.Programs(robot_server, mostar_web, source, server_args=["--sim", scene])
    try:
        driver = webtest.WebDriver(programs.work, window=(1120, 820))
        driver.get(programs.url("/#token=" + webtest.TOKEN))
        cell = webtest.wait_for("a bumper hit in the HUD",
                        lambda: (lambda t: t if "hit" in t else None)(text(driver, "hud-bumpers")), 60)
        banner = driver.js("const b = document.getElementById('bumper-alert');"
                           "return b.hidden ? '' : b.textContent;")
        print("HUD bumpers: %r, banner: %r" % (cell, banner))
        check(re.fullmatch(r"\d+ of \d+ hit", cell) is not None, "the HUD counts the hit segments")
        check("BUMPER" in banner and "rear" in banner, "the banner names the rear segment")
    except Exception as e:  # noqa: BLE001
        failures.append(repr(e))
        print("FAIL:", repr(e))
    finally:
        if driver:
            driver.quit()
        shutil.rmtree(scene_dir, ignore_errors=True)
    return programs.finish(failures)


if __name__ == "__main__":
    sys.exit(main())
