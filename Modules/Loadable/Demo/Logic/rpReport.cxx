#include "rpReport.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rpAtomicFile.h"

namespace rp {
namespace {
std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string Number(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.4g", value);
  return buffer;
}
}  // namespace

void Report::AddFigureBelow(const std::string& stage, const std::string& name, double value, const std::string& unit,
                            double maximum, const std::string& note) {
  this->Figures.push_back({stage, name, value, unit, "< " + Number(maximum) + " " + unit,
                           value < maximum ? Verdict::Pass : Verdict::Fail, note});
}

void Report::AddFigureAbove(const std::string& stage, const std::string& name, double value, const std::string& unit,
                            double minimum, const std::string& note) {
  this->Figures.push_back({stage, name, value, unit, "> " + Number(minimum) + " " + unit,
                           value > minimum ? Verdict::Pass : Verdict::Fail, note});
}

void Report::AddFigure(const std::string& stage, const std::string& name, double value, const std::string& unit,
                       const std::string& note) {
  this->Figures.push_back({stage, name, value, unit, "", Verdict::NotScored, note});
}

void Report::AddNotScored(const std::string& stage, const std::string& name, const std::string& why) {
  Figure f;
  f.Stage = stage;
  f.Name = name;
  f.Result = Verdict::NotScored;
  f.Note = why;
  f.Value = std::numeric_limits<double>::quiet_NaN();
  this->Figures.push_back(f);
}

void Report::AddPicture(const std::string& stage, const std::string& file, const std::string& caption) {
  this->Pictures.push_back({stage, file, caption});
}

void Report::AddMissingPicture(const std::string& stage, const std::string& file, const std::string& why) {
  this->MissingPictures.push_back({stage, file, why});
}

bool Report::AddPictureIf(bool drawn, const std::string& stage, const std::string& file, const std::string& caption,
                          const std::string& why) {
  if (drawn)
    this->AddPicture(stage, file, caption);
  else
    this->AddMissingPicture(stage, file, why);
  return drawn;
}

int Report::CountFailed() const {
  int failed = 0;
  for (const auto& f : this->Figures) failed += f.Result == Verdict::Fail;
  for (const auto& s : this->Stages) failed += !s.Ok;
  return failed;
}

std::string Report::ToHtml() const {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << Escape(this->Title)
       << "</title>\n<style>body{font-family:sans-serif;margin:2em;max-width:1400px}"
          "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:4px 8px;text-align:left}"
          "th{background:#eee}.pass{color:#070}.fail{color:#b00;font-weight:bold}.ns{color:#777}"
          "figure{display:inline-block;margin:0.5em;vertical-align:top}img{max-width:680px;border:1px solid #ddd}"
          "figcaption{font-size:90%;max-width:680px}</style></head><body>\n";
  html << "<h1>" << Escape(this->Title) << "</h1>\n";
  const int failed = this->CountFailed();
  html << "<p><b>" << (failed == 0 ? "All stages ran and every scored figure met its target."
                                    : std::to_string(failed) + " stage(s) or figure(s) failed.")
       << "</b></p>\n";
  if (!this->MissingPictures.empty()) {
    html << "<p class=\"fail\">Warning: " << this->MissingPictures.size() << " picture(s) could not be drawn:</p><ul>\n";
    for (const auto& p : this->MissingPictures)
      html << "<li>" << Escape(p.File) << " (" << Escape(p.Stage) << "): " << Escape(p.Caption) << "</li>\n";
    html << "</ul>\n";
  }
  for (const auto& note : this->Notes) html << "<p>" << Escape(note) << "</p>\n";

  html << "<h2>Stages</h2>\n<table><tr><th>stage</th><th>time (s)</th><th>result</th></tr>\n";
  for (const auto& s : this->Stages) {
    html << "<tr><td>" << Escape(s.Name) << "</td><td>" << Number(s.Seconds) << "</td><td class=\""
         << (s.Ok ? "pass\">ok" : "fail\">failed") << (s.Message.empty() ? "" : ": " + Escape(s.Message))
         << "</td></tr>\n";
  }
  html << "</table>\n<h2>Figures and targets</h2>\n<table><tr><th>stage</th><th>figure</th><th>value</th>"
          "<th>target</th><th>result</th><th>note</th></tr>\n";
  for (const auto& f : this->Figures) {
    const char* cls = f.Result == Verdict::Pass ? "pass" : f.Result == Verdict::Fail ? "fail" : "ns";
    const char* word = f.Result == Verdict::Pass ? "pass" : f.Result == Verdict::Fail ? "FAIL" : "not scored";
    html << "<tr><td>" << Escape(f.Stage) << "</td><td>" << Escape(f.Name) << "</td><td>"
         << (f.Value == f.Value ? Number(f.Value) + " " + Escape(f.Unit) : "—") << "</td><td>" << Escape(f.Target)
         << "</td><td class=\"" << cls << "\">" << word << "</td><td>" << Escape(f.Note) << "</td></tr>\n";
  }
  html << "</table>\n<h2>Pictures</h2>\n";
  std::string lastStage;
  for (const auto& p : this->Pictures) {
    if (p.Stage != lastStage) {
      html << "<h3>" << Escape(p.Stage) << "</h3>\n";
      lastStage = p.Stage;
    }
    html << "<figure><a href=\"" << Escape(p.File) << "\"><img src=\"" << Escape(p.File) << "\" alt=\""
         << Escape(p.Caption) << "\"></a><figcaption>" << Escape(p.Caption) << "</figcaption></figure>\n";
  }
  html << "</body></html>\n";
  return html.str();
}

std::string Report::ToJson() const {
  nlohmann::json doc;
  doc["title"] = this->Title;
  doc["stages"] = nlohmann::json::array();
  for (const StageRecord& s : this->Stages)
    doc["stages"].push_back({{"name", s.Name}, {"seconds", s.Seconds}, {"ok", s.Ok}, {"message", s.Message}});
  doc["figures"] = nlohmann::json::array();
  for (const Figure& f : this->Figures) {
    const char* result = f.Result == Verdict::Pass ? "pass" : f.Result == Verdict::Fail ? "fail" : "not scored";
    nlohmann::json value = std::isfinite(f.Value) ? nlohmann::json(f.Value) : nlohmann::json(nullptr);
    doc["figures"].push_back({{"stage", f.Stage}, {"name", f.Name}, {"value", value}, {"unit", f.Unit},
                              {"target", f.Target}, {"result", result}, {"note", f.Note}});
  }
  doc["pictures"] = nlohmann::json::array();
  for (const Picture& p : this->Pictures) doc["pictures"].push_back({{"stage", p.Stage}, {"file", p.File}});
  doc["picturesMissing"] = nlohmann::json::array();
  for (const Picture& p : this->MissingPictures)
    doc["picturesMissing"].push_back({{"stage", p.Stage}, {"file", p.File}, {"why", p.Caption}});
  for (const auto& [key, text] : this->Sections) {
    // A section that is not JSON is kept as its text rather than lost (it is a bug upstream).
    nlohmann::json section = nlohmann::json::parse(text, nullptr, false);
    doc[key] = section.is_discarded() ? nlohmann::json(text) : section;
  }
  return doc.dump(2) + "\n";
}

bool Report::Write(const std::string& path, std::string& error) const {
  const std::string json = path.size() > 5 && path.substr(path.size() - 5) == ".html"
                               ? path.substr(0, path.size() - 5) + ".json"
                               : path + ".json";
  return WriteFileAtomically(path, this->ToHtml(), error) && WriteFileAtomically(json, this->ToJson(), error);
}

}  // namespace rp
