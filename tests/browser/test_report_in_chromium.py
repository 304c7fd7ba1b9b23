"""The --report page in a real headless Chromium (Debian's ``chromium``, driven through Debian's chromedriver
with Selenium): it loads with no console error and fetches nothing, and every image on it is loaded and has a
picture in it (read back through a canvas in the browser, and decoded with PIL).

The page is made for real: a box through a sheet and a smaller one elsewhere, their contacts from the
continuous check, the regions' pictures rendered by VTK. The tests skip, saying why, only when Chromium or
chromedriver is not installed (``apt-get install chromium chromium-driver``; .ci/run installs them).
"""

import base64
import io
import shutil

import numpy as np
import pytest
from PIL import Image
from selenium import webdriver
from selenium.webdriver.chrome.service import Service

from usdksl.clock import StageClock
from usdksl.contacts.table import ContactTable
from usdksl.regions.table import RegionTable
from usdksl.reports.html_report import ShotSection, html_report
from usdksl.reports.pictures import region_pictures

from .report_scene import SPAN, contacts, hand_regions, scene

CHROMIUM = next((found for found in map(shutil.which, ("chromium", "chromium-browser")) if found), None)
CHROMEDRIVER = shutil.which("chromedriver")
#: Seconds the browser may take to load a page.
PAGE_LOAD_SECONDS = 60
#: Distinct colours an image has at least: a rendered picture or a plot, not one flat colour.
MIN_DISTINCT_COLORS = 20
DATA_PNG = "data:image/png;base64,"

pytestmark = pytest.mark.skipif(CHROMIUM is None or CHROMEDRIVER is None,
                                reason="Chromium or chromedriver is not installed "
                                       "(apt-get install chromium chromium-driver)")

#: Run in the page: for every <img>, whether it loaded, its natural size and how many distinct colours its
#: pixels have (drawn on a canvas; data: images do not taint it).
READ_IMAGES = """
return Array.from(document.images).map(function (image) {
  var result = {src: image.currentSrc || image.src, complete: image.complete, width: image.naturalWidth,
                height: image.naturalHeight, colors: 0};
  if (image.complete && image.naturalWidth > 0) {
    var canvas = document.createElement('canvas');
    canvas.width = image.naturalWidth;
    canvas.height = image.naturalHeight;
    var context = canvas.getContext('2d');
    context.drawImage(image, 0, 0);
    var data = context.getImageData(0, 0, canvas.width, canvas.height).data;
    var seen = new Set();
    for (var i = 0; i < data.length; i += 4) {
      seen.add(((data[i] << 16) | (data[i + 1] << 8) | data[i + 2]) + data[i + 3] * 16777216);
    }
    result.colors = seen.size;
  }
  return result;
});
"""


@pytest.fixture(scope="module")
def browser():
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                     "--disable-extensions", "--no-first-run", "--window-size=1280,2000"):
        options.add_argument(argument)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(options=options, service=Service(executable_path=CHROMEDRIVER))
    driver.set_page_load_timeout(PAGE_LOAD_SECONDS)
    yield driver
    driver.quit()


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    """The page of a run of two shots: the boxes through the sheet (pictures of both regions) and a clean one."""
    meshes = scene()
    table = contacts(meshes)
    regions = hand_regions(meshes, table)
    pictures = region_pictures(meshes, table, regions, regions.worst_first())
    found = ShotSection(shot="shots/box & sheet <v2>.usda", summary=f"usdksl: {table.count} contacting face pairs",
                        exit_code=1, clock=StageClock(), span=SPAN, table=table, regions=regions, pictures=pictures,
                        notes=["usdksl: warning: shots/box.usda: /World/Cloth: points are empty at time 3"])
    clean = ShotSection(shot="shots/clean.usda", summary="usdksl: clean", exit_code=0, clock=StageClock(),
                        span=SPAN, table=ContactTable.empty(None), regions=RegionTable.empty(None))
    path = tmp_path_factory.mktemp("report") / "report.html"
    path.write_text(html_report([found, clean]), encoding="utf-8")
    return path


def load(driver, path):
    """Open ``path`` and return (console entries, images as READ_IMAGES reads them, resources fetched)."""
    driver.get_log("browser")                     # drop what an earlier page said
    driver.get(path.as_uri())
    assert driver.execute_script("return document.readyState") == "complete"
    images = driver.execute_script(READ_IMAGES)
    fetched = driver.execute_script("return performance.getEntriesByType('resource').map(e => e.name)")
    return driver.get_log("browser"), images, fetched


def distinct_colors(source: str) -> int:
    image = Image.open(io.BytesIO(base64.b64decode(source[len(DATA_PNG):])))
    return int(np.unique(np.asarray(image.convert("RGB")).reshape(-1, 3), axis=0).shape[0])


def test_the_report_loads_cleanly_and_every_image_shows_a_picture(browser, report):
    console, images, fetched = load(browser, report)
    assert [entry for entry in console if entry["level"] in ("SEVERE", "ERROR")] == []
    assert fetched == []                                      # nothing from the network or the disk
    assert browser.title == "usdksl report"
    assert len(images) == 3                                   # the timeline and the two regions' pictures
    for image in images:
        assert image["src"].startswith(DATA_PNG)
        assert image["complete"] and image["width"] > 0 and image["height"] > 0
        assert image["colors"] >= MIN_DISTINCT_COLORS                     # read back in the browser
        assert distinct_colors(image["src"]) >= MIN_DISTINCT_COLORS       # and decoded here
    assert [(image["width"], image["height"]) for image in images[1:]] == [(640, 420), (640, 420)]
    heading = browser.find_element("css selector", "#shot-1 h2").text
    assert heading == "shots/box & sheet <v2>.usda"           # escaped on the page, shown as written


def test_the_checks_see_a_broken_image_and_a_console_error(browser, tmp_path):
    """The same checks on a page with a broken image, a blank one and a script error find all three."""
    blank = io.BytesIO()
    Image.new("RGB", (40, 30), (255, 255, 255)).save(blank, format="PNG")
    broken_page = tmp_path / "broken.html"
    broken_page.write_text(
        "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>broken</title></head><body>"
        f"<img src=\"{DATA_PNG}AAAA\"><img src=\"{DATA_PNG}{base64.b64encode(blank.getvalue()).decode()}\">"
        "<script>console.error('something failed')</script></body></html>", encoding="utf-8")
    console, images, _ = load(browser, broken_page)
    assert any("something failed" in entry["message"] for entry in console if entry["level"] == "SEVERE")
    assert images[0]["width"] == 0 and images[0]["colors"] == 0
    assert images[1]["complete"] and images[1]["width"] == 40 and images[1]["colors"] == 1
