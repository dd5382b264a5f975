#include "rockcal/reports/html_page.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "rockcal/core/format.h"
#include "rockcal/core/material.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/rock_shape.h"
#include "rockcal/observations/observations.h"
#include "rockcal/reports/html_report.h"
#include "rockcal/reports/svg.h"

namespace rockcal::reports::html {
namespace {

using core::FormatNumber;

using svg::Escape;
using svg::Label;

using core::kInf;

std::string Int(long v) { return std::to_string(v); }

constexpr const char* kCss = R"(
body{font-family:"DejaVu Sans",Helvetica,Arial,sans-serif;font-size:14px;line-height:1.4;color:#222;margin:0 auto;max-width:1060px;padding:16px 24px;}
h1{font-size:24px;margin:8px 0 4px;}
h2{font-size:19px;border-bottom:2px solid #6b8fb3;padding-bottom:3px;margin-top:32px;}
h3{font-size:15px;margin:18px 0 6px;}
p.lead{font-size:15px;margin:4px 0 10px;}
nav ol{columns:3;margin:6px 0 0;padding-left:22px;}
table{border-collapse:collapse;margin:6px 0 10px;font-size:13px;}
th,td{border:1px solid #ccc;padding:3px 7px;vertical-align:top;}
thead th{background:#eef2f6;}
table.kv th{text-align:left;background:#f6f6f6;font-weight:normal;white-space:nowrap;}
table.stats tbody th{text-align:left;font-weight:normal;background:#f6f6f6;}
td.n{text-align:right;white-space:nowrap;}
td.ok{color:#1a7f37;}td.bad{color:#b00020;font-weight:bold;}td.warn{color:#8a4b00;}
td.result{font-weight:bold;min-width:100px;}td.case{min-width:210px;}td.name{white-space:nowrap;}
tr.best td{background:#f2f8ec;}tr.fail td{background:#fdecee;}
table.wide{font-size:12px;}table.wide th,table.wide td{padding:3px 5px;}
.desc{display:block;font-size:11.5px;font-weight:normal;color:#555;max-width:300px;}.desc.warn{color:#8a4b00;}
p.verdict{font-size:15px;font-weight:bold;padding:5px 10px;border-left:5px solid #6b8fb3;background:#f4f7fa;}
p.verdict.ok{border-color:#1a7f37;}p.verdict.bad{border-color:#b00020;}
figure{margin:10px 0;display:inline-block;vertical-align:top;}
figcaption{font-size:12.5px;color:#444;max-width:860px;}
div.figs figure{margin-right:10px;}
svg{max-width:100%;height:auto;}
ul.legend{list-style:none;padding:0;margin:4px 0;font-size:12.5px;}
ul.legend li{display:inline-block;margin-right:14px;white-space:nowrap;}
ul.legend svg{vertical-align:middle;}
.halo{paint-order:stroke;stroke:#fff;stroke-width:3px;stroke-linejoin:round;}
.small{font-size:9.5px;}
p.note{font-size:12.5px;color:#444;}
p.warn{color:#8a4b00;background:#fff4e0;padding:4px 8px;}
code{font-size:12.5px;}
footer{margin-top:30px;font-size:12px;color:#666;border-top:1px solid #ccc;padding-top:6px;}
@page{size:A4;margin:14mm;}
@media print{body{max-width:none;padding:0;font-size:11px;}nav{display:none;}h2{break-after:avoid;}figure,table{break-inside:avoid;}section{break-before:auto;}}
)";

}  // namespace

std::string Show(double v) {
  if (std::isnan(v)) return "-";
  if (!std::isfinite(v)) return v > 0 ? "inf" : "-inf";
  const double a = std::fabs(v);
  if (a == 0.0) return "0";
  if (a >= 100.0) return FormatNumber(v, "%.0f");
  if (a >= 10.0) return FormatNumber(v, "%.1f");
  if (a >= 1.0) return FormatNumber(v, "%.2f");
  return FormatNumber(v, "%.3g");
}

std::string ShowPercent(double fraction) { return Show(100.0 * fraction) + " %"; }

std::string Percent(double fraction) { return FormatNumber(100.0 * fraction, "%.1f") + " %"; }

std::string Exact(double v) { return FormatNumber(v, "%.10g"); }

std::string Ref(const std::string& file, const std::string& pointer) {
  return file + "#" + pointer;
}

std::string RefCell(const std::string& ref, double value, const std::string& shown) {
  return "<td class=\"n\" data-json=\"" + Escape(ref) + "\" data-value=\"" + Exact(value) + "\">" +
         Escape(shown) + "</td>";
}

std::string RefSpan(const std::string& ref, double value, const std::string& shown) {
  return "<span data-json=\"" + Escape(ref) + "\" data-value=\"" + Exact(value) + "\">" +
         Escape(shown) + "</span>";
}

std::string RefText(const std::string& ref, const std::string& value) {
  return "<span data-json=\"" + Escape(ref) + "\" data-value=\"" + Escape(value) + "\">" +
         Escape(value) + "</span>";
}

std::string Td(const std::string& text, bool numeric) {
  return std::string(numeric ? "<td class=\"n\">" : "<td>") + Escape(text) + "</td>";
}

std::string Th(const std::string& text) { return "<th>" + Escape(text) + "</th>"; }

std::string Kv(const std::string& key, const std::string& value_html) {
  return "<tr><th>" + Escape(key) + "</th><td>" + value_html + "</td></tr>";
}

std::string Figure(const std::string& svg, const std::string& caption_html, double width) {
  return (width > 0 ? "<figure style=\"max-width:" + svg::Px(width) + "px\">"
                    : std::string("<figure>")) +
         svg + "<figcaption>" + caption_html + "</figcaption></figure>";
}

std::string Length(double m, sites::Units units) {
  if (units != sites::Units::kUS) return Show(m) + " m";
  return Show(m) + " m (" + Show(m / core::kFoot) + " ft)";
}

std::string Energy(double joules, sites::Units units) {
  if (units != sites::Units::kUS) return Show(joules * 1e-3) + " kJ";
  return Show(joules * 1e-3) + " kJ (" + Show(joules / kFtTon) + " ft-tons)";
}

std::string Speed(double mps, sites::Units units) {
  if (units != sites::Units::kUS) return Show(mps) + " m/s";
  return Show(mps) + " m/s (" + Show(mps / core::kFoot) + " ft/s)";
}

std::string CoordinateNumber(double m) {
  // Map coordinates reach 1e7 m (northings): to the decimetre there, to
  // four significant digits below 1000.
  if (!std::isfinite(m)) return Show(m);
  return std::fabs(m) >= 1000.0 ? FormatNumber(m, "%.1f") : Label(m);
}

std::string Coordinate(double m, sites::Units units) {
  if (units != sites::Units::kUS) return CoordinateNumber(m) + " m";
  return CoordinateNumber(m) + " m (" + CoordinateNumber(m / core::kFoot) + " ft)";
}

std::string PartitionPlace(const core::Partition& part, sites::Units units) {
  if (part.kind == core::Partition::Kind::kX) return "x = " + Coordinate(part.value, units);
  if (part.kind == core::Partition::Kind::kZ) return "z = " + Coordinate(part.value, units);
  auto point = [](const Eigen::Vector2d& v) {
    return "(" + CoordinateNumber(v.x()) + ", " + CoordinateNumber(v.y()) + ")";
  };
  if (part.line.empty()) return "line of no vertices";
  return "line of " + std::to_string(part.line.size()) + " vertices from " +
         point(part.line.front()) + " to " + point(part.line.back()) + " m";
}

std::string PageHtml(const Page& page) {
  std::string h =
      "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\">\n<head>\n"
      "<meta charset=\"utf-8\"/>\n<title>" +
      Escape(page.title) + "</title>\n<style>" + kCss +
      "</style>\n</head>\n<body>\n<header>\n<h1>" + page.heading_html +
      "</h1>\n<p class=\"lead\">" + page.lead_html + "</p>\n";
  if (!page.note_html.empty()) h += "<p class=\"note\">" + page.note_html + "</p>\n";
  h += "<nav><ol>";
  for (const Section& s : page.sections)
    h += "<li><a href=\"#" + Escape(s.id) + "\">" + Escape(s.title) + "</a></li>";
  h += "</ol></nav>\n</header>\n<main>\n";
  int number = 0;
  for (const Section& s : page.sections)
    h += "<section id=\"" + Escape(s.id) + "\">\n<h2>" + Int(++number) + ". " +
         (s.heading_html.empty() ? Escape(s.title) : s.heading_html) + "</h2>\n" + s.body_html +
         "\n</section>\n";
  h += "</main>\n<footer>" + page.footer_html + "</footer>\n</body>\n</html>\n";
  return h;
}

namespace {

// The site, its file and units, and the terrain grid.
std::string SiteKv(const core::Scene& sc, const std::string& site_file, sites::Units units) {
  const core::HeightGrid& g = sc.grid;
  const bool us = units == sites::Units::kUS;
  double zmin = kInf, zmax = -kInf;
  for (double z : g.z)
    if (std::isfinite(z)) zmin = std::min(zmin, z), zmax = std::max(zmax, z);
  if (!(zmax >= zmin)) zmin = 0.0, zmax = 1.0;
  if (zmax == zmin) zmax = zmin + 1.0;
  const bool one_cell_wide = g.nx <= 2 || g.ny <= 2;
  std::string s = "<table class=\"kv\">";
  s += Kv("Site", Escape(sc.name));
  if (!site_file.empty()) s += Kv("Site file", "<code>" + Escape(site_file) + "</code>");
  s += Kv("Units of the site file", us ? "US (ft, lbf/ft&#179;); this report shows SI and US units"
                                       : "SI (m, kN/m&#179;); this report shows SI units");
  int holes = 0;
  for (double z : g.z) holes += std::isfinite(z) ? 0 : 1;
  s += Kv(
      "Terrain grid",
      Escape(Int(g.nx) + " x " + Int(g.ny) + " nodes at a spacing of " + Length(g.spacing, units) +
             "; x " + CoordinateNumber(g.x0) + " to " + Coordinate(g.x(g.nx - 1), units) + ", y " +
             CoordinateNumber(g.y0) + " to " + Coordinate(g.y(g.ny - 1), units) + ", elevation " +
             CoordinateNumber(zmin) + " to " + Coordinate(zmax, units) +
             (holes ? "; " + Int(holes) + " nodes without data" : "") +
             (one_cell_wide ? "; a 2D profile one cell wide" : "")));
  s += "</table>";
  return s;
}

// The materials with their share of the slope and the contact law derived
// from each.
std::string MaterialsTable(const core::Scene& sc, sites::Units units) {
  const core::HeightGrid& g = sc.grid;
  std::vector<int> nodes(sc.materials.size(), 0);
  int valid = 0;
  for (std::size_t n = 0; n < g.z.size(); ++n)
    if (std::isfinite(g.z[n])) ++nodes[static_cast<std::size_t>(g.material[n])], ++valid;
  std::string s = "<h3>Materials</h3><table><thead><tr>" + Th("material") +
                  Th("share of the slope") + Th("hardness H") + Th("roughness R") +
                  Th("virtual sphere radius") + Th("restitution e") + Th("friction f") +
                  Th("rolling resistance") + Th("vegetation") + Th("contact time") +
                  Th("damping ratio (eq. 13)") +
                  "</tr></thead><tbody>";
  bool overridden = false;
  for (std::size_t k = 0; k < sc.materials.size(); ++k) {
    const core::Material& m = sc.materials[k];
    const core::ContactLaw law = core::DeriveContactLaw(m, sc.hardness_model);
    const double r = core::VirtualSphereRadius(m.roughness_m, g.spacing);
    auto mark = [&](bool b) {
      overridden = overridden || b;
      return std::string(b ? " *" : "");
    };
    s += "<tr>" + Td(m.id) +
         Td(Percent(valid ? static_cast<double>(nodes[k]) / valid : 0.0), true) +
         Td(FormatNumber(m.hardness, "%.3f"), true) +
         Td(m.roughness_m > 0 ? Length(m.roughness_m, units) : "0 (smooth facets)", true) +
         Td(std::isfinite(r) ? Length(r, units) : "-", true) +
         Td(FormatNumber(law.restitution, "%.3f") + mark(m.restitution.has_value()), true) +
         Td(FormatNumber(law.friction, "%.3f") + mark(m.friction.has_value()), true) +
         Td(FormatNumber(law.rolling_resistance, "%.3f") + mark(m.rolling_resistance.has_value()),
            true) +
         Td(m.vegetation_pa > 0 ? Show(m.vegetation_pa * 1e-3) + " kPa" : "-", true) +
         Td(Show(law.contact_time * 1e3) + " ms", true) +
         Td(FormatNumber(law.damping_ratio, "%.3f") + " (" +
                FormatNumber(law.eq13_damping_ratio, "%.3f") + ")",
            true) +
         "</tr>";
  }
  s += "</tbody></table><p class=\"note\">Derived from hardness by the default model: e = H, "
       "friction " +
       FormatNumber(sc.hardness_model.friction_soft, "%.2f") + " - (" +
       FormatNumber(sc.hardness_model.friction_soft, "%.2f") + " - " +
       FormatNumber(sc.hardness_model.friction_hard, "%.2f") + ") H, rolling resistance " +
       FormatNumber(sc.hardness_model.rolling_soft, "%.2f") + " to " +
       FormatNumber(sc.hardness_model.rolling_hard, "%.2f") + " with H" +
       (overridden ? "; * set in the site file instead" : "") +
       ". The damping ratio is the one that gives e with a contact that never pulls; the manual's "
       "eq. 13 value is "
       "shown beside it. Virtual sphere radius r = (R&#178; + (s/2)&#178;) / (2R).</p>";
  return s;
}

// A point in plan, "(888630.0, 6671517.5) m", with feet beside for a US site.
std::string Point(const Eigen::Vector2d& p, sites::Units units) {
  std::string s = "(" + CoordinateNumber(p.x()) + ", " + CoordinateNumber(p.y()) + ") m";
  if (units == sites::Units::kUS)
    s += " (" + CoordinateNumber(p.x() / core::kFoot) + ", " +
         CoordinateNumber(p.y() / core::kFoot) + ") ft";
  return s;
}

// Where group `grp` is released: zone or point, height or elevation, velocity.
std::string GroupRelease(const core::RockGroup& grp, sites::Units units) {
  std::string release;
  if (!grp.release.zone.empty()) {
    const Eigen::Vector2d cen = observations::ReleaseCentroid(grp.release);
    release = "zone of " + Int(static_cast<long>(grp.release.zone.size())) + " vertices around " +
              Point(cen, units);
  } else {
    release = "point " + Point(grp.release.point, units);
  }
  if (grp.release.elevation)
    release += ", dropped from elevation " + Coordinate(*grp.release.elevation, units);
  else if (grp.release.height > 0)
    release += ", " + Length(grp.release.height, units) + " above the ground";
  if (grp.release.velocity.norm() > 0)
    release +=
        ", initial velocity (" + Label(grp.release.velocity.x()) + ", " +
        Label(grp.release.velocity.y()) + ", " + Label(grp.release.velocity.z()) + ") m/s" +
        (units == sites::Units::kUS ? " (" + Label(grp.release.velocity.x() / core::kFoot) + ", " +
                                          Label(grp.release.velocity.y() / core::kFoot) + ", " +
                                          Label(grp.release.velocity.z() / core::kFoot) + ") ft/s"
                                    : std::string());
  return release;
}

// The rock groups: count, shape, size, unit weight, mass and release.
std::string RockGroupsTable(const core::Scene& sc, sites::Units units) {
  std::string s = "<h3>Rock groups</h3><table><thead><tr>" + Th("group") + Th("rocks") +
                  Th("shape") + Th("size") + Th("unit weight") + Th("mass") + Th("release") +
                  "</tr></thead><tbody>";
  for (std::size_t k = 0; k < sc.groups.size(); ++k) {
    const core::RockGroup& grp = sc.groups[k];
    const core::GroupExtent extent = core::GroupBodies(grp, sc.gravity);
    const core::RockBody& a = extent.lightest;
    const core::RockBody& b = extent.heaviest;
    const std::string size =
        !grp.inventory.empty()
            ? "inventory of " + Int(static_cast<long>(grp.inventory.size())) + " blocks"
        : grp.size_min == grp.size_max ? Length(grp.size_min, units)
        : units != sites::Units::kUS   ? Show(grp.size_min) + "-" + Show(grp.size_max) + " m"
                                       : Show(grp.size_min) + "-" + Show(grp.size_max) + " m (" +
                                           Show(grp.size_min / core::kFoot) + "-" +
                                           Show(grp.size_max / core::kFoot) + " ft)";
    const bool us = units == sites::Units::kUS;
    const std::string mass =
        a.mass == b.mass
            ? Show(a.mass) + " kg" + (us ? " (" + Show(a.mass / kPound) + " lb)" : "")
            : Show(a.mass) + "-" + Show(b.mass) + " kg" +
                  (us ? " (" + Show(a.mass / kPound) + "-" + Show(b.mass / kPound) + " lb)" : "");
    s += "<tr>" + Td(Int(static_cast<long>(k + 1)), true) + Td(Int(grp.count), true) +
         Td(grp.inventory.empty() ? core::ShapeToString(grp.shape) : "blocks") + Td(size) +
         Td(Show(grp.unit_weight * 1e-3) + " kN/m³" +
            (us ? " (" + Show(grp.unit_weight / kLbfPerFt3) + " lbf/ft³)" : "")) +
         Td(mass) + Td(GroupRelease(grp, units)) + "</tr>";
  }
  return s + "</tbody></table>";
}

// The partitions, with the rocks that passed each when `passage` is given.
std::string PartitionsTable(const core::Scene& sc, sites::Units units,
                            const PartitionPassage* passage) {
  std::string s;
  if (!sc.partitions.empty()) {
    s += "<h3>Partitions</h3><table><thead><tr>" + Th("partition") + Th("kind") + Th("at") +
         (passage ? Th("rocks passed") : std::string()) + "</tr></thead><tbody>";
    for (std::size_t p = 0; p < sc.partitions.size(); ++p) {
      const core::Partition& part = sc.partitions[p];
      s += "<tr>" +
           (passage ? "<td><a href=\"#" + Escape(PartitionSectionId(part.id)) + "\">" +
                          Escape(part.id) + "</a></td>"
                    : Td(part.id)) +
           Td(part.kind == core::Partition::Kind::kX   ? "X (vertical plane)"
              : part.kind == core::Partition::Kind::kZ ? "Z (ground elevation contour)"
                                                       : "barrier (line in plan)") +
           Td(PartitionPlace(part, units));
      if (passage) {
        const int passed = p < passage->passed.size() ? passage->passed[p] : 0;
        s += Td(Int(passed) + " (" +
                    Percent(passage->rocks ? static_cast<double>(passed) / passage->rocks : 0.0) +
                    ")",
                true);
      }
      s += "</tr>";
    }
    s += "</tbody></table>";
  }
  return s;
}

}  // namespace

std::string SiteTables(const core::Scene& scene, const std::string& site_file, sites::Units units,
                       const PartitionPassage* passage) {
  return SiteKv(scene, site_file, units) + MaterialsTable(scene, units) +
         RockGroupsTable(scene, units) + PartitionsTable(scene, units, passage);
}

std::string SiteNotes(const std::vector<std::string>& notes) {
  if (notes.empty()) return "";
  std::string s = "<h3>What the site reader did</h3><ul class=\"notes\">";
  for (const std::string& n : notes) s += "<li>" + Escape(n) + "</li>";
  return s + "</ul>";
}

}  // namespace rockcal::reports::html
