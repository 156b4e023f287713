#!/usr/bin/env python3
"""The workbench's first screen and edit latency, measured in Chromium (a benchmark, not a test).

    python3 benches/gen_workbooks.py --out /tmp/wb grid-100000
    cargo build --release
    python3 benches/workbench_latency.py /tmp/wb/grid-100000.xlsx [--ncsheet target/release/ncsheet] [--edits 30]

It starts `ncsheet serve FILE`, opens the printed URL in headless Chromium (chromium-driver and
Selenium, as tests/workbench_browser.py), and measures on the page with performance.now():

- first screen: from navigation start (the page's timeOrigin) to the first grid cells drawn
  with their values (the body's data-ready and the cell A1 showing 1);
- edit latency: from the Enter key in the formula bar (a typed number for A{n} of the last
  row) to the dependent cell K{n} showing its new value, for --edits edits; the median and
  the worst are printed. The last row is shown (the name box goes there first), so each edit
  recomputes one row of 10 formulas and the page redraws what changed.

The figures go to benches/README.md by hand; the budget is a median under 50 ms and a first
screen under 1.5 s.
"""

import argparse
import statistics
import subprocess
import sys
import tempfile
import time

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support.ui import WebDriverWait

EDIT = """
const [cellName, input, before, done] = arguments;
const formula = document.getElementById('formula');
formula.focus();
formula.value = input;
const start = performance.now();
formula.dispatchEvent(new KeyboardEvent('keydown', { key: 'Enter', bubbles: true }));
(function poll() {
  const cell = document.querySelector('#cells [data-cell="' + cellName + '"]');
  if (cell && cell.textContent !== before) done(performance.now() - start);
  else requestAnimationFrame(poll);
})();
"""

FIRST_SCREEN = """
const done = arguments[0];
(function poll() {
  const a1 = document.querySelector('#cells [data-cell="A1"]');
  if (document.body.dataset.ready === '1' && a1 && a1.textContent === '1') done(performance.now());
  else requestAnimationFrame(poll);
})();
"""


def browser(profile):
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for flag in ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", f"--user-data-dir={profile}", "--window-size=1400,800"]:
        options.add_argument(flag)
    return webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)


def go_to(driver, name):
    box = driver.find_element(By.ID, "namebox")
    box.clear()
    box.send_keys(name, Keys.ENTER)
    # The name box shows what was typed at once: wait for the grid's selection to get there.
    selected = "const c = document.querySelector('#cells .c.sel'); return c ? c.dataset.cell : null;"
    WebDriverWait(driver, 30).until(lambda d: d.execute_script(selected) == name)
    WebDriverWait(driver, 30).until(lambda d: d.execute_script("return document.activeElement.id;") == "scroller")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("file", help="grid-N.xlsx from benches/gen_workbooks.py")
    parser.add_argument("--ncsheet", default="target/release/ncsheet")
    parser.add_argument("--edits", type=int, default=30)
    parser.add_argument("--rows", type=int, default=100_000, help="N of grid-N")
    args = parser.parse_args()

    server = subprocess.Popen([args.ncsheet, "serve", args.file], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        opened = time.monotonic()
        url = server.stdout.readline().strip()
        print(f"server ready in {time.monotonic() - opened:.2f} s (opening the workbook): {url.split('?')[0]}")
        with tempfile.TemporaryDirectory() as profile:
            driver = browser(profile)
            try:
                driver.set_script_timeout(120)
                driver.get(url)
                first = driver.execute_async_script(FIRST_SCREEN)
                print(f"first screen: {first:.0f} ms after the page was asked for")
                n = args.rows
                go_to(driver, f"A{n}")
                WebDriverWait(driver, 30).until(
                    lambda d: d.execute_script(f"const c = document.querySelector('#cells [data-cell=\"A{n}\"]'); return c && c.textContent;") == str(n))
                times = []
                for i in range(args.edits):
                    value = n + 1 + i
                    # K{n} reads A{n} through the row's formulas: the edit is done when it
                    # shows something else (the bench needs no copy of the formulas).
                    before = driver.execute_script(f"return document.querySelector('#cells [data-cell=\"K{n}\"]').textContent;")
                    go_to(driver, f"A{n}")
                    times.append(driver.execute_async_script(EDIT, f"K{n}", str(value), before))
                times.sort()
                print(f"edit latency over {len(times)} edits: median {statistics.median(times):.1f} ms, "
                      f"best {times[0]:.1f} ms, worst {times[-1]:.1f} ms")
            finally:
                driver.quit()
    finally:
        server.kill()
        server.wait()


if __name__ == "__main__":
    sys.exit(main())
