// The page every HTML report of rockcal is built on (report.html of simulate
// and calibrate, and of the studies): one self-contained XHTML-compatible file
// with inline CSS, a numbered table of contents and numbered sections; the
// cell helpers that tie a shown number to its JSON value; and the site
// section's tables, which need only the scene.
#ifndef ROCKCAL_REPORTS_HTML_PAGE_H_
#define ROCKCAL_REPORTS_HTML_PAGE_H_

#include <string>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/sites/site.h"

namespace rockcal::reports::html {

// US units beside SI (metres in a foot: core::kFoot): kilograms in a pound,
// N/m^3 in a lbf/ft^3, and joules in a ft-ton (foot times short ton-force, as
// CRSP reports kinetic energy).
inline constexpr double kPound = 0.45359237;
inline constexpr double kLbfPerFt3 = 4.4482216152605 / (core::kFoot * core::kFoot * core::kFoot);
inline constexpr double kFtTon = 2000.0 * 4.4482216152605 * core::kFoot;

// ---- Numbers and cells ---------------------------------------------------------

// A value as shown in tables: three significant digits, no exponent for
// ordinary magnitudes ("1234", "56.7", "8.90", "0.0123"); "-" for NaN.
std::string Show(double v);
// A fraction shown in percent with Show's digits ("2.35 %", "0.0412 %").
std::string ShowPercent(double fraction);
// A fraction shown in percent with one decimal ("12.5 %").
std::string Percent(double fraction);
// The exact value behind a shown number, for machines: %.10g as in the CSV files.
std::string Exact(double v);
// "FILE#POINTER", e.g. Ref("summary.json", "/partitions/0/passed").
std::string Ref(const std::string& file, const std::string& pointer);

// A numeric table cell (or a span) showing `shown` (plain text) whose exact
// value is `value` at `ref`: data-json="ref" data-value="Exact(value)".
std::string RefCell(const std::string& ref, double value, const std::string& shown);
std::string RefSpan(const std::string& ref, double value, const std::string& shown);
// A span showing the string `value` found at `ref` (data-value is the string).
std::string RefText(const std::string& ref, const std::string& value);
// Table cells of plain text (right-aligned when numeric), a header cell, and
// a key-value row whose value is markup.
std::string Td(const std::string& text, bool numeric = false);
std::string Th(const std::string& text);
std::string Kv(const std::string& key, const std::string& value_html);
// A figure whose caption wraps at `width` px (the picture's width) when > 0.
std::string Figure(const std::string& svg, const std::string& caption_html, double width = 0.0);
// Figures in the site's units (docs/reference/outputs.md#units-of-the-report):
// an SI site's in SI only, a US site's in SI with US units beside.
// A length: "12.3 m", or "12.3 m (40.4 ft)" for a US site.
std::string Length(double m, sites::Units units);
// A kinetic energy: "123 kJ", or "123 kJ (45.4 ft-tons)" for a US site.
std::string Energy(double joules, sites::Units units);
// A speed: "12.3 m/s", or "12.3 m/s (40.4 ft/s)" for a US site.
std::string Speed(double mps, sites::Units units);
// A map coordinate or elevation, rounded one way wherever the report prints
// it: the number alone (CoordinateNumber) or with its unit, "888630.0 m", or
// for a US site "121.9 m (400.0 ft)" (an SI site's coordinates are never
// converted).
std::string CoordinateNumber(double m);
std::string Coordinate(double m, sites::Units units);
// Where a partition is: "x = ...", "z = ..." (Coordinate), or a barrier's
// line, "line of N vertices from (x, y) to (x, y) m".
std::string PartitionPlace(const core::Partition& part, sites::Units units);

// ---- The page ----------------------------------------------------------------

struct Section {
  std::string id;            // <section id>, and the link target in the contents
  std::string title;         // plain text, in the contents
  std::string heading_html;  // the <h2> after the number; empty: the escaped title
  std::string body_html;
};

struct Page {
  std::string title;         // <title>, plain text
  std::string heading_html;  // the <h1>
  std::string lead_html;     // the first paragraph (<p class="lead">)
  std::string note_html;     // a note under it (<p class="note">), "" for none
  std::vector<Section> sections;
  std::string footer_html;
};

// The whole document: the doctype, the head with the inline CSS, the header
// (heading, lead, note, contents), the numbered sections and the footer. One
// file, no scripts, nothing loaded from the network, printable on A4.
std::string PageHtml(const Page& page);

// ---- The site ------------------------------------------------------------------

// The rocks that passed each partition of a run, for the partitions table.
struct PartitionPassage {
  std::vector<int> passed;  // per partition of the scene
  int rocks = 0;            // rocks in the run
};

// The site as simulated: site name, file and units; the grid; the materials
// with their derived contact parameters; the rock groups; the partitions.
// With `passage` (a report that has a section per partition) the partitions
// table also gives the rocks passed and links each partition to its section
// (PartitionSectionId).
std::string SiteTables(const core::Scene& scene, const std::string& site_file, sites::Units units,
                       const PartitionPassage* passage = nullptr);
// "What the site reader did": the notes as a list; "" when there are none.
std::string SiteNotes(const std::vector<std::string>& notes);

}  // namespace rockcal::reports::html

#endif  // ROCKCAL_REPORTS_HTML_PAGE_H_
