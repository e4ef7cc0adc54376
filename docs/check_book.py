"""Open the built book in headless Chromium and check that its pages load and figures show.

Every page of the book (the entry page, the pages of ``docs/``, the executed notebooks) is
loaded, one per Chromium run, in a frame of a small checking page; once it has loaded and MathJax
has typeset it, every image is read back: loaded, with a ``naturalWidth`` above 0. A page
fails if it does not load, if an image does not decode or has no width, if an executed
notebook shows no figure or a figure without alternative text, or if a notebook's TeX is left
untypeset while MathJax is in the book. Screenshots of the entry page and of one notebook are
saved for a person to look at.

Usage: ``python docs/check_book.py [build/site] [--screenshots build/book-check]``; exit
status 1 on any failure. Needs Chromium (Debian: ``apt-get install chromium``).
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

REPOSITORY = Path(__file__).resolve().parents[1]
SITE = REPOSITORY / "build" / "site"
#: Pages shown in screenshots: the entry page and a notebook with figures and equations.
SCREENSHOT_PAGES = ("index.html", "notebooks/executed/02_wiener_deconvolution.html")
BROWSERS = ("chromium", "chromium-browser", "google-chrome")
#: Virtual milliseconds Chromium may spend loading and typesetting a page before it reports.
VIRTUAL_TIME_BUDGET_MS = 30_000

CHECK_PAGE = """<!doctype html><html><body><pre id="result">pending</pre><script>
function report(result) { document.getElementById('result').textContent = JSON.stringify(result); }
function inspect(frame) {
  const doc = frame.contentDocument;
  return {
    title: doc.title,
    text_length: doc.body ? doc.body.innerText.length : 0,
    images: Array.from(doc.images).map(image => ({
      src: (image.getAttribute('src') || '').slice(0, 60),
      width: image.naturalWidth, decoded: image.complete && image.naturalHeight > 0,
      alt: image.getAttribute('alt') || ''})),
    typeset_math: doc.querySelectorAll('.MathJax_CHTML').length,
    tex_source: /\\$[^$\\n]+\\$/.test(doc.body ? doc.body.innerText : ''),
  };
}
function typeset(frame) {
  const mathjax = frame.contentWindow.MathJax;
  if (!mathjax || !mathjax.Hub) return Promise.resolve();
  return new Promise(resolve => mathjax.Hub.Queue(resolve));
}
const frame = document.createElement('iframe');
frame.style.width = '1280px'; frame.style.height = '900px';
frame.onload = () => typeset(frame).then(() => report(inspect(frame)))
  .catch(error => report({error: String(error)}));
frame.src = PAGE;
document.body.appendChild(frame);
</script></body></html>
"""


def find_browser() -> str | None:
    """Return the path of an installed Chromium, or ``None``.

    Returns
    -------
    str or None
        The first of ``chromium``, ``chromium-browser`` and ``google-chrome`` on the ``PATH``.
    """
    return next((path for name in BROWSERS if (path := shutil.which(name))), None)


def book_pages(site: Path) -> list[str]:
    """List the book's pages to check, relative to the site's root.

    Parameters
    ----------
    site : Path
        The built site (``build/site``).

    Returns
    -------
    list of str
        ``index.html``, the pages of ``docs/`` and the executed notebooks' pages.
    """
    pages = ["index.html"]
    for folder in ("docs", "notebooks/executed"):
        pages += [str(page.relative_to(site)) for page in sorted((site / folder).glob("*.html"))]
    return pages


def headless(browser: str, *arguments: str, timeout_s: float = 120) -> str:
    """Run headless Chromium with the given arguments and return what it prints.

    Parameters
    ----------
    browser : str
        Path of the Chromium executable.
    *arguments : str
        Further command-line arguments (the URL last).
    timeout_s : float
        Wall-clock limit in seconds.

    Returns
    -------
    str
        Chromium's standard output.
    """
    with tempfile.TemporaryDirectory() as profile:
        command = [
            browser,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-dev-shm-usage",
            "--allow-file-access-from-files",
            f"--user-data-dir={profile}",
            *arguments,
        ]
        done = subprocess.run(command, capture_output=True, text=True, timeout=timeout_s)
    return done.stdout


def inspect_page(browser: str, site: Path, page: str) -> dict:
    """Load one page of the book in Chromium and report what it shows.

    Parameters
    ----------
    browser : str
        Path of the Chromium executable.
    site : Path
        The built site.
    page : str
        The page, relative to the site's root.

    Returns
    -------
    dict
        The page's title, the length of its text, each image's source (cut), natural width
        and whether it loaded, the number of typeset equations and whether TeX source shows;
        or ``{"error": ...}`` when the page did not report.
    """
    check_page = site / "_check_book.html"
    check_page.write_text(CHECK_PAGE.replace("PAGE", json.dumps(page)), encoding="utf-8")
    try:
        dom = headless(
            browser,
            f"--virtual-time-budget={VIRTUAL_TIME_BUDGET_MS}",
            "--dump-dom",
            check_page.as_uri(),
        )
    except subprocess.TimeoutExpired:
        return {"error": "Chromium timed out"}
    finally:
        check_page.unlink()
    start = dom.find('<pre id="result">') + len('<pre id="result">')
    report = dom[start : dom.find("</pre>", start)]
    if report.strip() in ("", "pending"):
        return {"error": "the page did not finish loading"}
    return json.loads(report.replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&"))


def page_failures(page: str, result: dict, mathjax_in_book: bool) -> list[str]:
    """Return what is wrong with one page's report (nothing when it passes).

    Parameters
    ----------
    page : str
        The page, relative to the site's root.
    result : dict
        Its report from :func:`inspect_page`.
    mathjax_in_book : bool
        Whether the book carries MathJax, so that TeX must be typeset.

    Returns
    -------
    list of str
        One line per failure.
    """
    if "error" in result:
        return [f"{page}: {result['error']}"]
    failures = []
    if not result["title"] or result["text_length"] < 200:
        failures.append(f"{page}: did not load (title {result['title']!r})")
    for image in result["images"]:
        if not image["decoded"] or image["width"] == 0:
            failures.append(f"{page}: image {image['src']} does not show")
    if page.startswith("notebooks/") and not any(image["width"] for image in result["images"]):
        failures.append(f"{page}: no figure shows")
    if page.startswith("notebooks/"):
        for image in result["images"]:
            if not image.get("alt", "").strip():
                failures.append(f"{page}: figure {image['src']} has no alternative text")
    if page.startswith("notebooks/") and mathjax_in_book and result["tex_source"]:
        failures.append(f"{page}: TeX shown as source ({result['typeset_math']} typeset)")
    return failures


def main() -> int:
    """Check the built book; print one line per page and return the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("site", nargs="?", type=Path, default=SITE, help="the built site")
    parser.add_argument(
        "--screenshots",
        type=Path,
        default=REPOSITORY / "build" / "book-check",
        help="folder for the screenshots",
    )
    arguments = parser.parse_args()
    browser = find_browser()
    if browser is None:
        print("Chromium not found (Debian: apt-get install chromium)", file=sys.stderr)
        return 1
    site = arguments.site.resolve()
    pages = book_pages(site)
    mathjax_in_book = (site / "assets" / "mathjax" / "MathJax.js").is_file()
    failures = []
    for page in pages:
        result = inspect_page(browser, site, page)
        failures += page_failures(page, result, mathjax_in_book)
        shown = sum(1 for image in result.get("images", []) if image["width"])
        equations = result.get("typeset_math", 0)
        print(f"{page}: {shown} images shown, {equations} equations typeset")
    arguments.screenshots.mkdir(parents=True, exist_ok=True)
    for page in filter(lambda page: (site / page).is_file(), SCREENSHOT_PAGES):
        picture = arguments.screenshots / (Path(page).stem + ".png")
        headless(
            browser,
            "--window-size=1280,1600",
            "--virtual-time-budget=20000",
            f"--screenshot={picture}",
            (site / page).as_uri(),
        )
        print(f"screenshot: {picture}")
    for failure in failures:
        print(f"FAIL {failure}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
