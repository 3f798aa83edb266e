#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""`cifs gallery` writes an index.html that a browser shows whole (docs/experiments.md, "The gallery").

A small gallery — a curve with its SVG and automaton, a surface with its PLY, and an experiment whose
description and output names need escaping — is written from a temporary examples folder (the
shipped shapes, smaller images), then its index.html is loaded by headless Chromium with a check
script added (in a copy: the page itself has no script). The test fails unless
- the page loads and every <img> resolves (naturalWidth > 0), every link target exists, and every
  link is relative, inside the gallery folder;
- every image the gallery wrote (PNG, SVG, walked here) is shown, and every other file linked;
- each experiment's name and description appear as text, not markup;
- the check itself sees a broken image (a copy of the page with one missing image must fail it);
- driven through chromedriver like a user (with --chromedriver): each section's images are a grid (several
  cards side by side), every card has a caption naming its file, a click on a thumbnail shows the image
  full size over the page (its own size, or as large as the window allows), and the
  keyboard alone (Tab, Enter) opens a thumbnail, moves to the next image and closes the view.

    tests/gallery/test_index.py --cli build/apps/cifs --examples examples --chromium chromium \
        --chromedriver chromedriver --work /tmp/g
"""
import argparse
import html.parser
import json
import os
import shutil
import subprocess
import sys
import urllib.parse
from pathlib import Path

# Shown literally by the page: markup, an ampersand, quotes (the description is the user's text).
ODD_DESCRIPTION = 'A <b>circle</b> & its "exact" weights <script>alert(1)</script> \'quoted\''
EXPERIMENTS = {
    "wave.json": {"name": "wave", "description": "A rational cubic and its automaton",
                  "shape": "../shapes/wave.json", "evaluation": {"depth": 5},
                  "render": {"width": 240, "height": 120, "control_net": True},
                  "outputs": {"exr": "wave.exr", "png": "wave.png", "svg": "wave.svg",
                              "automaton_svg": "wave.automaton.svg", "automaton_dot": "wave.automaton.dot"}},
    "hills.json": {"name": "hills", "description": "A bicubic surface, framed tightly",
                   "shape": "../shapes/hills.json", "evaluation": {"depth": 3},
                   "camera": {"projection": "perspective", "margin": 0.02},
                   "render": {"width": 200, "height": 150}, "outputs": {"exr": "hills.exr", "png": "hills.png",
                                                                         "ply": "hills.ply"}},
    "odd.json": {"name": "odd <name> & co", "description": ODD_DESCRIPTION,
                 "shape": "../shapes/circle.json", "evaluation": {"depth": 4},
                 "render": {"width": 120, "height": 120},
                 "outputs": {"exr": "odd one.exr", "png": "odd #1 & more.png", "obj": "odd 100%.obj"}},
}

CHECK_SCRIPT = """<script>
window.addEventListener("load", () => {
  const images = [...document.images].map(i => ({src: i.src, ok: i.complete && i.naturalWidth > 0}));
  const links = [...document.querySelectorAll("a[href]")].map(a => a.href);
  const sections = [...document.querySelectorAll("section")].map(s => ({
    name: s.querySelector("h2") ? s.querySelector("h2").textContent : "",
    description: s.querySelector("p") ? s.querySelector("p").textContent : "",
    markup: s.querySelectorAll("p *, h2 *").length}));
  const pre = document.createElement("pre");
  pre.id = "cifs-check";
  pre.textContent = JSON.stringify({title: document.title, images, links, sections});
  document.body.appendChild(pre);
});
</script>"""


class Raw(html.parser.HTMLParser):
    """The page's own references and elements, as written (before the browser resolves them)."""

    def __init__(self):
        super().__init__()
        self.refs, self.tags = [], set()

    def handle_starttag(self, tag, attrs):
        self.tags.add(tag)
        self.refs += [value for name, value in attrs if name in ("src", "href")]


def browse(args, page):
    """The check script's JSON for `page` (a copy of index.html with the script), from Chromium's DOM."""
    command = [args.chromium, "--headless", "--disable-gpu", "--no-sandbox", "--virtual-time-budget=20000",
               "--dump-dom", page.as_uri()]
    result = subprocess.run(command, capture_output=True, text=True, timeout=300)
    if result.returncode != 0:
        sys.exit(f"chromium failed ({result.returncode}): {result.stderr[-2000:]}")
    parser = PreText()
    parser.feed(result.stdout)
    if parser.text is None:
        sys.exit("the page did not load: no check result in Chromium's DOM\n" + result.stdout[-2000:])
    return json.loads(parser.text)


class PreText(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.inside, self.text = False, None

    def handle_starttag(self, tag, attrs):
        self.inside = tag == "pre" and ("id", "cifs-check") in attrs

    def handle_data(self, data):
        if self.inside:
            self.text = (self.text or "") + data

    def handle_endtag(self, tag):
        self.inside = False


def interact(args, index):
    """Failures of the page driven like a user (see the module's docstring)."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    failures = []
    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which(args.chromium) or args.chromium
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1200,900",
                 "--disable-dev-shm-usage"):
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service(shutil.which(args.chromedriver) or args.chromedriver),
                              options=options)
    try:
        driver.get(index.as_uri())
        open_viewers = "return [...document.querySelectorAll('.viewer')].filter(v => getComputedStyle(v).display " \
                       "!== 'none').map(v => v.id)"
        # A grid: the scheme figures' section has cards side by side, all of one width.
        grids = driver.find_elements(By.CSS_SELECTOR, ".figures")
        if not grids or any(driver.execute_script("return getComputedStyle(arguments[0]).display", g) != "grid"
                            for g in grids):
            failures.append("the images are not laid out as a grid")
        widest = max(grids, key=lambda g: len(g.find_elements(By.TAG_NAME, "figure")))
        cards = widest.find_elements(By.TAG_NAME, "figure")
        tops = [c.rect["y"] for c in cards]
        if len(cards) < 4 or tops.count(tops[0]) < 3 or len({round(c.rect["width"]) for c in cards}) != 1:
            failures.append(f"no grid of cards: {len(cards)} cards, {tops.count(tops[0])} in the first row")
        # Captions: every card names its file.
        for figure in driver.find_elements(By.TAG_NAME, "figure"):
            caption = figure.find_element(By.TAG_NAME, "figcaption").text
            src = urllib.parse.unquote(figure.find_element(By.TAG_NAME, "img").get_attribute("src"))
            if not caption or not src.endswith(caption.split(": ")[0]):
                failures.append(f"card {src}: caption {caption!r}")
        # A click shows the image full size over the page (its own size, or as large as the window allows);
        # "close" goes back.
        first = driver.find_element(By.CSS_SELECTOR, "figure a")
        first.click()
        viewers = driver.execute_script(open_viewers)
        if viewers != ["v0"]:
            failures.append(f"a click on the first thumbnail shows the viewers {viewers}")
        else:
            viewer = driver.find_element(By.ID, "v0")
            big = viewer.find_element(By.TAG_NAME, "img")
            nw, nh, ww, wh = driver.execute_script(
                "const i = arguments[0]; return [i.naturalWidth, i.naturalHeight, innerWidth, innerHeight]", big)
            scale = min(1, 0.92 * ww / nw, 0.8 * wh / nh)
            size = big.rect
            if abs(size["width"] - nw * scale) > 2 or abs(size["height"] - nh * scale) > 2:
                failures.append(f"the viewer shows {size['width']:.0f}×{size['height']:.0f} of a {nw}×{nh} image "
                                f"in a {ww}×{wh} window (expected {nw * scale:.0f}×{nh * scale:.0f})")
            viewer.find_element(By.CLASS_NAME, "close").click()
            if driver.execute_script(open_viewers):
                failures.append("'close' leaves a viewer open")
        # The keyboard alone: Tab to the first thumbnail, Enter opens it, Tab to "next", Enter, Tab to "close",
        # Enter.
        driver.get(index.as_uri() + "#")

        def press(key):
            ActionChains(driver).send_keys(key).perform()

        def tab_to(test, limit=40):
            for _ in range(limit):
                press(Keys.TAB)
                if driver.execute_script(f"const a = document.activeElement; return {test};"):
                    return True
            return False
        if not tab_to("a.parentElement && a.parentElement.tagName === 'FIGURE'"):
            failures.append("Tab never reaches a thumbnail")
        else:
            press(Keys.ENTER)
            opened = driver.execute_script(open_viewers)
            if len(opened) != 1:
                failures.append(f"Enter on a thumbnail shows the viewers {opened}")
            elif not tab_to("a.classList.contains('next')", 6):
                failures.append("Tab does not reach the viewer's 'next'")
            else:
                press(Keys.ENTER)
                after = driver.execute_script(open_viewers)
                expected = f"v{int(opened[0][1:]) + 1}"
                if after != [expected]:
                    failures.append(f"Enter on 'next' in {opened[0]} shows {after}, expected {expected}")
                elif not tab_to("a.classList.contains('close')", 6):
                    failures.append("Tab does not reach the viewer's 'close'")
                else:
                    press(Keys.ENTER)
                    if driver.execute_script(open_viewers):
                        failures.append("Enter on 'close' leaves a viewer open")
    finally:
        driver.quit()
    return failures


def local(url):
    assert url.startswith("file://"), url
    return Path(urllib.parse.unquote(urllib.parse.urlparse(url).path))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cli", required=True)
    ap.add_argument("--examples", required=True, type=Path)
    ap.add_argument("--chromium", required=True)
    ap.add_argument("--chromedriver", help="with selenium: drive the page like a user")
    ap.add_argument("--work", required=True, type=Path)
    args = ap.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    examples = args.work / "examples"
    (examples / "experiments").mkdir(parents=True)
    (examples / "shapes").symlink_to(args.examples.resolve() / "shapes")
    for name, experiment in EXPERIMENTS.items():
        (examples / "experiments" / name).write_text(json.dumps(experiment))
    out = args.work / "out"
    run = subprocess.run([args.cli, "gallery", str(out), "--examples", str(examples), "--quiet"],
                         capture_output=True, text=True, timeout=600)
    if run.returncode != 0:
        sys.exit(f"cifs gallery failed ({run.returncode}): {run.stderr}")
    index = out / "index.html"
    failures = []
    if not index.is_file():
        sys.exit(f"no {index}")
    page = index.read_text()

    # As written: relative references only, no script, nothing from the network.
    raw = Raw()
    raw.feed(page)
    for ref in raw.refs:
        parts = urllib.parse.urlparse(ref)
        if parts.scheme or parts.netloc or ref.startswith("/") or ".." in Path(parts.path).parts:
            failures.append(f"not a relative link inside the folder: {ref}")
    for tag in ("script", "link", "iframe", "object"):
        if tag in raw.tags:
            failures.append(f"the page has a <{tag}>")

    # In the browser.
    checked = out / ".check.html"
    checked.write_text(page.replace("</body>", CHECK_SCRIPT + "</body>"))
    seen = browse(args, checked)
    if seen["title"] != "cifs gallery":
        failures.append(f"title {seen['title']!r}")
    for image in seen["images"]:
        if not image["ok"]:
            failures.append(f"image does not resolve: {image['src']}")
    for link in seen["links"]:
        if not local(link).is_file():
            failures.append(f"link target missing: {link}")
    shown = {local(i["src"]).resolve() for i in seen["images"]}
    linked = {local(a).resolve() for a in seen["links"]}
    written = [p for p in out.rglob("*") if p.is_file() and p.name not in ("index.html", ".check.html")]
    for path in written:
        is_image = path.suffix.lower() in (".png", ".svg")
        if is_image and path.resolve() not in shown:
            failures.append(f"image not shown: {path.relative_to(out)}")
        if not is_image and path.resolve() not in linked:
            failures.append(f"file not linked: {path.relative_to(out)}")
    if len(written) < 9 + 40:  # our 3 experiments' 9 files + the scheme figures
        failures.append(f"only {len(written)} files written")
    sections = {s["name"]: s for s in seen["sections"]}
    for experiment in EXPERIMENTS.values():
        s = sections.get(experiment["name"])
        if s is None:
            failures.append(f"no section named {experiment['name']!r} among {list(sections)}")
        elif s["description"] != experiment["description"] or s["markup"]:
            failures.append(f"{experiment['name']!r}: description shown as {s['description']!r}, "
                            f"{s['markup']} element(s) inside")

    # The check can fail: one image missing in a copy of the page is reported.
    broken = out / ".broken.html"
    broken.write_text(page.replace('src="wave.png"', 'src="no_such.png"').replace("</body>",
                                                                                 CHECK_SCRIPT + "</body>"))
    bad = [i["src"] for i in browse(args, broken)["images"] if not i["ok"]]
    if {Path(local(src)).name for src in bad} != {"no_such.png"}:  # its thumbnail and its viewer
        failures.append(f"the check does not see a missing image: {bad}")
    checked.unlink()
    broken.unlink()
    if args.chromedriver:
        failures += interact(args, index)

    for f in failures:
        print("FAIL:", f)
    print(f"{len(seen['images'])} images, {len(seen['links'])} links, {len(written)} files: "
          f"{'ok' if not failures else f'{len(failures)} failure(s)'}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
