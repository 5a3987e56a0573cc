// The pages made from one rendered report HTML (docs/rendering.md#screen-print-and-single-file):
// the screen page (index.html) loads only what it shows, the print page feeds WeasyPrint, and
// the optional single-file page carries its stylesheet and figures inside it.
//
// The templates draw each figure as a pair of images, an SVG for the screen and a PNG for
// print:
//   <figure class="fig"><img class="screen-only" src="figures/s.svg" alt=".."><img
//   class="print-only" src="figures/s.png" alt=".."><figcaption>..</figcaption></figure>
// Each page keeps one image of the pair, so a browser never downloads the print PNGs.
#pragma once

#include <filesystem>
#include <string>

namespace chatterlab::app {

// The screen page: every `<img class="print-only" ...>` removed; every `<img class="screen-only"
// ...>` loads lazily (loading="lazy": an image below the fold or inside a closed <details>
// loads when it is about to be seen); every `<figure class="fig">` gets id="fig-<stem>" (its
// image's file stem, unique in the page) and, when `out`/figures/<stem>.csv exists, a "data"
// link to that CSV at the end of its caption.
std::string screen_page(const std::string& html, const std::filesystem::path& out);

// The print page: every `<img class="screen-only" ...>` removed, every <details> open, and the
// same figure ids as the screen page.
std::string print_page(const std::string& html);

// The single-file page from the screen page: the stylesheet link to report.css replaced by the
// stylesheet's text, and every image under figures/ embedded as a base64 data URI. Other links
// (figure data, results.json, per-test files) stay relative to the report folder. Throws
// RenderError naming a file that cannot be read.
std::string single_file_page(const std::string& screen_html, const std::filesystem::path& out);

// "test-" + `id` with every character outside [A-Za-z0-9_-] as '-': a test's anchor.
std::string test_anchor(const std::string& id);

// RFC 4648 base64 of `bytes`.
std::string base64(const std::string& bytes);

}  // namespace chatterlab::app
