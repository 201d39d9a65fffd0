// SPDX-License-Identifier: MIT
#include "program/read_program.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "program/machine_json.h"

namespace omnislice {

namespace {

// Forward-map plug-in per machine kind: machine axis values -> part-frame tip and nozzle axis.
// cartesian3 is m = q with u = +Z; the machines issue adds rotary4 / table5 / robot6 here.
struct KindReplay {
  std::vector<std::string> letters;  // G-code axis words, in ProgramMove::axes order
  std::function<void(const MachineProfile&, const std::vector<double>& axes, Eigen::Vector3d& tip,
                     Eigen::Vector3d& axis)>
      toPart;
};

const KindReplay* replayFor(const std::string& kind) {
  static const std::map<std::string, KindReplay> kinds = {
      {"cartesian3",
       {{"X", "Y", "Z"},
        [](const MachineProfile&, const std::vector<double>& a, Eigen::Vector3d& tip,
           Eigen::Vector3d& axis) {
          tip = {a[0], a[1], a[2]};
          axis = Eigen::Vector3d::UnitZ();
        }}},
  };
  auto it = kinds.find(kind);
  return it == kinds.end() ? nullptr : &it->second;
}

std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

bool startsWith(const std::string& s, const char* prefix) {
  return s.compare(0, std::char_traits<char>::length(prefix), prefix) == 0;
}

// Strict finite number from the whole (trimmed) text.
bool parseNumber(const std::string& text, double& out) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  out = std::strtod(t.c_str(), &end);
  return end == t.c_str() + t.size() && std::isfinite(out);
}

bool parseInt(const std::string& text, int& out) {
  double v = 0;
  if (!parseNumber(text, v) || v != std::floor(v) || std::abs(v) > 1e9) return false;
  out = static_cast<int>(v);
  return true;
}

// Feature names of other slicers' `;TYPE:` lines mapped to the format's names.
std::string featureFromType(std::string type) {
  std::string up;
  for (char c : trim(type)) up += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  static const std::map<std::string, std::string> names = {
      {"WALL-OUTER", "wall-outer"},       {"EXTERNAL PERIMETER", "wall-outer"},
      {"OUTER WALL", "wall-outer"},       {"WALL-INNER", "wall-inner"},
      {"PERIMETER", "wall-inner"},        {"INNER WALL", "wall-inner"},
      {"OVERHANG PERIMETER", "wall-outer"}, {"SKIN", "skin"},
      {"SOLID INFILL", "skin"},           {"TOP SOLID INFILL", "skin"},
      {"BOTTOM SOLID INFILL", "skin"},    {"FILL", "infill"},
      {"INTERNAL INFILL", "infill"},      {"SPARSE INFILL", "infill"},
      {"SUPPORT", "support"},             {"SUPPORT-INTERFACE", "support"},
      {"SUPPORT MATERIAL", "support"},    {"SUPPORT MATERIAL INTERFACE", "support"},
      {"BRIDGE", "bridge"},               {"BRIDGE INFILL", "bridge"},
      {"WALL-OUTER", "wall-outer"}};
  auto it = names.find(up);
  if (it != names.end()) return it->second;
  std::string low;
  for (char c : trim(type)) low += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return low;
}

struct Word {
  char letter;
  double value;
};

}  // namespace

ParsedProgram readProgram(const std::string& text) {
  ParsedProgram r;
  int lineNo = 0;
  if (trim(text).empty()) {
    r.status = Status::EmptyInput;
    r.message = "program text is empty";
    return r;
  }
  auto fail = [&](Status s, const std::string& msg) {
    ParsedProgram f;
    f.status = s;
    f.message = "line " + std::to_string(lineNo) + ": " + msg;
    return f;
  };

  bool haveMachine = false, haveExtrusionMode = false, haveLayerHeight = false;
  bool haveLineWidth = false, haveNozzle = false, haveFilament = false;
  double plainLayerHeight = 0;  // `;Layer height:` of other slicers
  const KindReplay* replay = replayFor("cartesian3");
  std::vector<double> axes(replay->letters.size(), 0.0);
  double e = 0, feed = 0;
  bool relativeAll = false;   // G91
  bool relativeE = false;     // M83 (kept across G90, as Marlin does)
  bool sawMoves = false;
  int layer = -1, part = 0;
  std::string feature;
  std::set<int> layers;
  bool firstContentLine = true;

  size_t pos = 0;
  while (pos <= text.size()) {
    size_t nl = text.find('\n', pos);
    if (nl == std::string::npos) nl = text.size();
    std::string raw = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++lineNo;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    const std::string lineText = trim(raw);
    if (lineText.empty()) {
      if (nl == text.size()) break;
      continue;
    }
    const bool first = firstContentLine;
    firstContentLine = false;

    if (lineText[0] == ';') {
      const std::string c = trim(lineText.substr(1));
      if (first && startsWith(c, "omnislice ")) {
        // "; omnislice <version> <method> <date>"
        std::vector<std::string> parts;
        size_t p = 0;
        while (p < c.size()) {
          size_t q = c.find(' ', p);
          if (q == std::string::npos) q = c.size();
          if (q > p) parts.push_back(c.substr(p, q - p));
          p = q + 1;
        }
        if (parts.size() >= 3) r.method = parts[2];
      } else if (startsWith(c, "omnislice:")) {
        const std::string rest = c.substr(10);
        const size_t sp = rest.find_first_of(" \t");
        const std::string key = rest.substr(0, sp);
        const std::string value = sp == std::string::npos ? "" : trim(rest.substr(sp));
        if (key == "machine") {
          if (sawMoves) return fail(Status::ParseError, "machine header after the first move");
          MachineParseResult m = machineFromJson(value);
          if (!m.ok()) return fail(Status::ParseError, m.message);
          replay = replayFor(m.machine.kind);
          if (!replay) {
            return fail(Status::UnsupportedFormat,
                        "machine kind '" + m.machine.kind + "' cannot be replayed by this build");
          }
          r.machine = m.machine;
          axes.assign(replay->letters.size(), 0.0);
          haveMachine = true;
        } else if (key == "placement") {
          nlohmann::json j = nlohmann::json::parse(value, nullptr, false);
          if (j.is_discarded() || !j.is_array() || j.size() != 16) {
            return fail(Status::ParseError, "placement must be a JSON array of 16 numbers");
          }
          for (int i = 0; i < 16; ++i) {
            if (!j[i].is_number() || !std::isfinite(j[i].get<double>())) {
              return fail(Status::ParseError, "placement entry " + std::to_string(i) +
                                                  " is not a finite number");
            }
            r.placement(i / 4, i % 4) = j[i].get<double>();
          }
        } else if (key == "extrusion") {
          nlohmann::json j = nlohmann::json::parse(value, nullptr, false);
          if (j.is_discarded() || !j.is_object() || !j.contains("mode") ||
              !j["mode"].is_string()) {
            return fail(Status::ParseError, "extrusion header must be {\"mode\":...}");
          }
          const std::string mode = j["mode"].get<std::string>();
          if (mode != "absolute" && mode != "relative") {
            return fail(Status::ParseError, "extrusion mode must be absolute or relative");
          }
          r.absoluteExtrusion = mode == "absolute";
          relativeE = !r.absoluteExtrusion;
          haveExtrusionMode = true;
          if (j.contains("filament_diameter")) {
            const auto& f = j["filament_diameter"];
            if (!f.is_number() || !std::isfinite(f.get<double>()) || f.get<double>() <= 0) {
              return fail(Status::ParseError, "filament_diameter must be a positive number");
            }
            r.filamentDiameter = f.get<double>();
            haveFilament = true;
          }
        } else if (key == "feed") {
          nlohmann::json j = nlohmann::json::parse(value, nullptr, false);
          if (j.is_discarded() || !j.is_object()) {
            return fail(Status::ParseError, "feed header must be a JSON object");
          }
        } else if (key == "setting") {
          const size_t eq = value.find('=');
          if (eq == std::string::npos) return fail(Status::ParseError, "setting without '='");
          const std::string name = trim(value.substr(0, eq));
          const std::string v = trim(value.substr(eq + 1));
          // The first value of a key is the effective one (writers put resolved values first).
          struct Numeric {
            const char* name;
            double* target;
            bool* seen;
          } numerics[] = {{"layer_height", &r.layerHeight, &haveLayerHeight},
                          {"line_width", &r.lineWidth, &haveLineWidth},
                          {"nozzle_diameter", &r.nozzleDiameter, &haveNozzle},
                          {"filament_diameter", &r.filamentDiameter, &haveFilament}};
          for (Numeric& n : numerics) {
            if (name != n.name || *n.seen) continue;
            double x = 0;
            if (!parseNumber(v, x) || x <= 0) {
              return fail(Status::ParseError, "setting " + name + " must be a positive number");
            }
            *n.target = x;
            *n.seen = true;
          }
        } else if (key == "layer") {
          if (!parseInt(value, layer)) return fail(Status::ParseError, "bad layer index");
          layers.insert(layer);
        } else if (key == "feature") {
          feature = value;
        } else if (key == "part") {
          const std::string idx = value.substr(0, value.find(' '));
          if (!parseInt(idx, part)) return fail(Status::ParseError, "bad part index");
        }
        // Other omnislice: keys (end, future additions) carry no replay facts.
      } else if (startsWith(c, "LAYER:")) {
        if (!parseInt(c.substr(6), layer)) return fail(Status::ParseError, "bad ;LAYER: index");
        layers.insert(layer);
      } else if (c == "LAYER_CHANGE") {
        layer = layer < 0 ? 0 : layer + 1;
        layers.insert(layer);
      } else if (startsWith(c, "TYPE:")) {
        feature = featureFromType(c.substr(5));
      } else if (startsWith(c, "Layer height:")) {
        double x = 0;
        if (parseNumber(c.substr(13), x) && x > 0) plainLayerHeight = x;
      } else if (startsWith(c, "layer_height =")) {
        double x = 0;
        if (parseNumber(c.substr(14), x) && x > 0 && plainLayerHeight == 0) plainLayerHeight = x;
      }
      continue;
    }

    // ---- command line: strip comments, split words ----
    std::string code = lineText.substr(0, lineText.find(';'));
    const size_t paren = code.find('(');
    if (paren != std::string::npos) code = code.substr(0, paren);
    code = trim(code);
    if (code.empty()) continue;
    // Line numbers "N123 ... *cs" of host protocols.
    if (code[0] == 'N' || code[0] == 'n') {
      size_t p = 1;
      while (p < code.size() && std::isdigit(static_cast<unsigned char>(code[p]))) ++p;
      code = trim(code.substr(p));
    }
    const size_t star = code.find('*');
    if (star != std::string::npos) code = trim(code.substr(0, star));
    if (code.empty()) continue;
    const char cmdLetter = static_cast<char>(std::toupper(static_cast<unsigned char>(code[0])));
    size_t p = 1;
    while (p < code.size() && (std::isdigit(static_cast<unsigned char>(code[p])) || code[p] == '.'))
      ++p;
    int cmdNumber = 0;
    if (cmdLetter != 'G' && cmdLetter != 'M') continue;  // T0 etc.: nothing to replay
    if (!parseInt(code.substr(1, p - 1), cmdNumber)) {
      // Sub-codes like G29.1 or M600.1: nothing this reader replays.
      continue;
    }
    const bool isMove = cmdLetter == 'G' && (cmdNumber == 0 || cmdNumber == 1);
    const bool isG92 = cmdLetter == 'G' && cmdNumber == 92;
    const bool isG28 = cmdLetter == 'G' && cmdNumber == 28;
    if (cmdLetter == 'G' && (cmdNumber == 2 || cmdNumber == 3)) {
      return fail(Status::UnsupportedFormat, "arc moves (G2/G3) are not supported");
    }
    if (cmdLetter == 'G' && cmdNumber == 20) {
      return fail(Status::UnsupportedFormat, "inch units (G20) are not supported");
    }
    if (cmdLetter == 'G' && cmdNumber == 90) relativeAll = false;
    if (cmdLetter == 'G' && cmdNumber == 91) relativeAll = true;
    if (cmdLetter == 'M' && cmdNumber == 82) relativeE = false;
    if (cmdLetter == 'M' && cmdNumber == 83) relativeE = true;
    if (!isMove && !isG92 && !isG28) continue;

    std::vector<Word> words;
    while (p < code.size()) {
      if (std::isspace(static_cast<unsigned char>(code[p]))) {
        ++p;
        continue;
      }
      const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(code[p])));
      if (!std::isalpha(static_cast<unsigned char>(letter))) {
        return fail(Status::ParseError, std::string("unexpected character '") + code[p] + "'");
      }
      ++p;
      const char* begin = code.c_str() + p;
      char* end = nullptr;
      const double v = std::strtod(begin, &end);
      if (end == begin) {
        if (isG28) {  // "G28 X Y" homes the named axes
          words.push_back({letter, 0.0});
          continue;
        }
        return fail(Status::ParseError, std::string("word ") + letter + " has no number");
      }
      if (!std::isfinite(v)) {
        return fail(Status::ParseError, std::string("word ") + letter + " is not finite");
      }
      p += static_cast<size_t>(end - begin);
      words.push_back({letter, v});
    }
    auto axisIndex = [&](char letter) -> int {
      for (size_t i = 0; i < replay->letters.size(); ++i) {
        if (replay->letters[i][0] == letter) return static_cast<int>(i);
      }
      return -1;
    };

    if (isG28) {
      // Homing: positions become unknown to a replay; the convention here is 0.
      if (words.empty()) std::fill(axes.begin(), axes.end(), 0.0);
      for (const Word& w : words) {
        const int i = axisIndex(w.letter);
        if (i >= 0) axes[i] = 0.0;
      }
      continue;
    }
    if (isG92) {
      if (words.empty()) {
        std::fill(axes.begin(), axes.end(), 0.0);
        e = 0;
      }
      for (const Word& w : words) {
        if (w.letter == 'E') e = w.value;
        const int i = axisIndex(w.letter);
        if (i >= 0) axes[i] = w.value;
      }
      continue;
    }

    // G0 / G1
    std::vector<double> next = axes;
    double filament = 0;
    bool motionWord = false, eWord = false;
    for (const Word& w : words) {
      if (w.letter == 'F') {
        if (w.value <= 0) return fail(Status::ParseError, "feed F must be positive");
        feed = w.value;
        continue;
      }
      if (w.letter == 'E') {
        eWord = true;
        if (relativeAll || relativeE) {
          filament = w.value;
          e += w.value;
        } else {
          filament = w.value - e;
          e = w.value;
        }
        continue;
      }
      const int i = axisIndex(w.letter);
      if (i < 0) continue;  // words of axes this kind does not have (e.g. A on cartesian3)
      motionWord = true;
      next[i] = relativeAll ? axes[i] + w.value : w.value;
    }
    if (!motionWord && !eWord) continue;  // feed-only line
    const bool moved = next != axes;
    if (!moved && filament == 0) {
      axes = next;
      continue;
    }
    ProgramMove m;
    Eigen::Vector3d axisUnused;
    replay->toPart(r.machine, axes, m.from, axisUnused);
    replay->toPart(r.machine, next, m.to, m.axis);
    m.filament = filament;
    m.feedMmPerMin = feed;
    m.layer = layer;
    m.part = part;
    m.feature = feature;
    m.axes = next;
    m.line = lineNo;
    r.moves.push_back(std::move(m));
    if (filament > 0 && !haveExtrusionMode) {
      // Without a header, the mode of the first extruding move is the program's mode.
      r.absoluteExtrusion = !(relativeAll || relativeE);
      haveExtrusionMode = true;
    }
    sawMoves = true;
    axes = next;
  }

  if (!haveMachine) {
    r.machine = MachineProfile{};  // cartesian3, no declared limits
    if (haveNozzle) r.machine.nozzle.diameter = r.nozzleDiameter;
  }
  if (!haveNozzle) r.nozzleDiameter = r.machine.nozzle.diameter;
  if (!haveLineWidth) r.lineWidth = 1.125 * r.nozzleDiameter;  // usual default width
  if (!haveLayerHeight) {
    if (plainLayerHeight > 0) {
      r.layerHeight = plainLayerHeight;
    } else {
      // From the steps between the Z levels of extruding moves (median step).
      std::vector<double> zs;
      for (const ProgramMove& m : r.moves) {
        if (m.filament > 0 && (m.to - m.from).norm() > 0) zs.push_back(std::round(m.to.z() * 1e4) / 1e4);
      }
      std::sort(zs.begin(), zs.end());
      zs.erase(std::unique(zs.begin(), zs.end()), zs.end());
      std::vector<double> steps;
      for (size_t i = 1; i < zs.size(); ++i) steps.push_back(zs[i] - zs[i - 1]);
      if (!steps.empty()) {
        std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
        r.layerHeight = steps[steps.size() / 2];
      } else if (!zs.empty() && zs.front() > 0) {
        r.layerHeight = zs.front();
      }
    }
  }
  r.layerCount = static_cast<int>(layers.size());
  if (r.method.empty()) r.method = "unknown";
  return r;
}

}  // namespace omnislice
