// SPDX-License-Identifier: MIT
// Reader of every program kind of PROGRAM-FORMAT.md.
// - G-code (first content line not starting with '#'): cartesian3, rotary4, table5 by the header's
//   machine (cartesian3 without one); axis words from gcodeAxisLetters() (the profile's axis_letters).
// - Robot joint CSV and URScript (first content line starting with '#'): robot6; URScript is told
//   apart by its `def` line. CSV rows are moves from the previous row's pose (the first row is the
//   start pose). URScript: movej / servoj joint targets with `t=` seconds, the extruder rate from
//   set_analog_out(port, v) / per_mm_s of the `# omnislice:extruder` header, sleep(t) feeds
//   filament without motion; movel (tool-space interpolation) is refused as UnsupportedFormat.
// Every move is replayed through forwardMap(); moves whose angular values change are cut by
// interpolateMachineMove() (chords within 0.01 mm, axis steps within 2 degrees), each piece with
// its share of the filament (E is linear in the move parameter like every axis) and the machine
// values at its end.
#include "program/read_program.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string_view>

#include "common/math_constants.h"
#include "kinematics/kinematics.h"
#include "program/interpolate_machine_move.h"
#include "machine/machine_json.h"

namespace omnislice {

namespace {

std::string_view trimView(std::string_view s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

std::string trim(const std::string& s) { return std::string(trimView(s)); }

// std::strtod on the text [begin, end) as if it ended there: the characters used (0 when no number
// starts there) and the value. Plain decimals whose digits form an integer m <= 2^53 and whose
// decimal exponent e has |e| <= 22 are converted as m * 10^e or m / 10^-e: m and 10^|e| are exact
// doubles, so that one correctly rounded operation gives the correctly rounded value, the one
// strtod returns (Clinger's fast path). Everything else (more digits, larger exponents, inf, nan,
// hexadecimal) goes to strtod itself.
size_t scanNumber(const char* begin, const char* end, double& out) {
  auto viaStrtod = [&]() {
    const std::string text(begin, end);
    char* stop = nullptr;
    out = std::strtod(text.c_str(), &stop);
    return static_cast<size_t>(stop - text.c_str());
  };
  static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                      1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                      1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  constexpr uint64_t kDigitLimit = ((uint64_t(1) << 53) - 9) / 10;  // m * 10 + 9 <= 2^53
  auto digit = [](char c) { return c >= '0' && c <= '9'; };
  const char* s = begin;
  while (s < end && std::isspace(static_cast<unsigned char>(*s))) ++s;
  bool negative = false;
  if (s < end && (*s == '+' || *s == '-')) negative = *s++ == '-';
  uint64_t m = 0;
  int exponent = 0;
  bool digits = false;
  const char* integer = s;
  for (; s < end && digit(*s); ++s, digits = true) {
    if (m > kDigitLimit) return viaStrtod();
    m = m * 10 + uint64_t(*s - '0');
  }
  if (s - integer == 1 && *integer == '0' && s < end && (*s == 'x' || *s == 'X')) return viaStrtod();
  if (s < end && *s == '.') {
    for (++s; s < end && digit(*s); ++s, digits = true, --exponent) {
      if (m > kDigitLimit) return viaStrtod();
      m = m * 10 + uint64_t(*s - '0');
    }
  }
  if (!digits) return viaStrtod();
  if (s < end && (*s == 'e' || *s == 'E')) {
    const char* t = s + 1;
    bool negativeExponent = false;
    if (t < end && (*t == '+' || *t == '-')) negativeExponent = *t++ == '-';
    if (t < end && digit(*t)) {  // else the 'e' is not part of the number
      int e = 0;
      for (; t < end && digit(*t); ++t) e = e < 100000 ? e * 10 + (*t - '0') : e;
      exponent += negativeExponent ? -e : e;
      s = t;
    }
  }
  if (exponent < -22 || exponent > 22) return viaStrtod();
  const double v = exponent < 0 ? double(m) / kPow10[-exponent] : double(m) * kPow10[exponent];
  out = negative ? -v : v;
  return static_cast<size_t>(s - begin);
}

bool startsWith(const std::string& s, const char* prefix) {
  return s.compare(0, std::char_traits<char>::length(prefix), prefix) == 0;
}

// Strict finite number from the whole (trimmed) text.
bool parseNumber(std::string_view text, double& out) {
  const std::string_view t = trimView(text);
  if (t.empty()) return false;
  return scanNumber(t.data(), t.data() + t.size(), out) == t.size() && std::isfinite(out);
}

bool parseInt(std::string_view text, int& out) {
  double v = 0;
  if (!parseNumber(text, v) || v != std::floor(v) || std::abs(v) > 1e9) return false;
  out = static_cast<int>(v);
  return true;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  size_t p = 0;
  while (true) {
    const size_t q = s.find(sep, p);
    out.push_back(s.substr(p, q == std::string::npos ? std::string::npos : q - p));
    if (q == std::string::npos) break;
    p = q + 1;
  }
  return out;
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
      {"BRIDGE", "bridge"},               {"BRIDGE INFILL", "bridge"}};
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

enum class Format { Gcode, Csv, UrScript, Rapid, Krl };

constexpr size_t kMaxPieces = 20000000;  // replayed pieces per program (about 4 GB of moves)

class Reader {
 public:
  explicit Reader(const std::string& text) : text_(text) {}

  ParsedProgram run();

 private:
  bool failed() const { return status_ != Status::Ok; }
  void fail(Status s, const std::string& msg) {
    if (failed()) return;
    status_ = s;
    message_ = "line " + std::to_string(lineNo_) + ": " + msg;
  }
  void comment(const std::string& body, bool first);
  void gcodeLine(std::string_view lineText);
  void csvRow(const std::string& lineText);
  void scriptLine(const std::string& lineText);
  void rapidLine(const std::string& lineText);
  void krlLine(const std::string& lineText);
  // A joint-space move to controller angles `deg` (RAPID, KRL) lasting t seconds at the current
  // extruder value; the first target is the start pose.
  void controllerMove(const std::array<double, 6>& deg, double t);
  // Filament fed at the current extruder value for t seconds without motion.
  void controllerWait(double t);
  bool setMachine(const std::string& json);
  // Replays the move a -> b (first n values) with `filament`; feedMmPerMin < 0 derives the feed
  // from durationS and the part-frame length.
  void emit(const MachineValues& a, const MachineValues& b, double filament, double feedMmPerMin,
            double durationS);

  const std::string& text_;
  ParsedProgram r_;
  Status status_ = Status::Ok;
  std::string message_;
  int lineNo_ = 0;
  Format format_ = Format::Gcode;
  int n_ = 3;  // values of the machine kind
  std::array<bool, 6> angular_{};  // isAngularAxis(kind, i) of the machine kind (cartesian3: none)
  bool haveMachine_ = false, haveExtrusionMode_ = false, haveLayerHeight_ = false;
  bool haveLineWidth_ = false, haveNozzle_ = false, haveFilament_ = false;
  double plainLayerHeight_ = 0;  // `;Layer height:` of other slicers
  bool sawMoves_ = false;
  int layer_ = -1, part_ = 0;
  uint16_t feature_ = 0;  // index into r_.features
  // The current feature marker: its index in r_.features, added there on first use.
  void setFeature(const std::string& name);
  std::set<int> layers_;
  // G-code state
  std::vector<std::string> letters_{"X", "Y", "Z"};
  std::vector<Word> words_;  // of the current line (kept for its capacity)
  MachineValues values_{};
  double e_ = 0, feed_ = 0;
  bool relativeAll_ = false, relativeE_ = false;
  // robot state
  bool sawRow_ = false, inDef_ = false, defEnded_ = false, called_ = false;
  double analogScale_ = 0;  // per mm/s of filament, from the extruder header
  int analogPort_ = 0;
  double analog_ = 0;       // current analog value
  std::string analogSignal_;  // RAPID: the extruder's signal name
  double percent_ = 100;       // KRL: BAS(#VEL_PTP, p)
  bool moduleEnded_ = false;   // RAPID: ENDMODULE seen
};

void Reader::setFeature(const std::string& name) {
  const auto at = std::find(r_.features.begin(), r_.features.end(), name);
  if (at != r_.features.end()) {
    feature_ = static_cast<uint16_t>(at - r_.features.begin());
    return;
  }
  // Feature names come from the program's own markers: a program naming more than a few hundred
  // is malformed (Omnislice's writers use about ten).
  if (r_.features.size() >= 1024) return fail(Status::ParseError, "more than 1024 distinct feature markers");
  feature_ = static_cast<uint16_t>(r_.features.size());
  r_.features.push_back(name);
}

bool Reader::setMachine(const std::string& json) {
  if (sawMoves_) {
    fail(Status::ParseError, "machine header after the first move");
    return false;
  }
  MachineParseResult m = machineFromJson(json);
  if (!m.ok()) {
    // An unknown kind (a newer build's machine) is UnsupportedFormat, anything else ParseError.
    fail(m.status == Status::UnsupportedFormat ? m.status : Status::ParseError, m.message);
    return false;
  }
  const int n = machineAxisCount(m.machine.kind);
  if (format_ == Format::Gcode && m.machine.kind == MachineKind::Robot6) {
    // `;` comments and a robot6 machine: a KUKA KRL program.
    format_ = Format::Krl;
    r_.format = "krl";
    r_.absoluteExtrusion = false;
  }
  if (format_ != Format::Gcode && m.machine.kind != MachineKind::Robot6) {
    fail(Status::ParseError, "a robot program needs a robot6 machine, not '" + std::string(machineKindName(m.machine.kind)) + "'");
    return false;
  }
  r_.machine = m.machine;
  n_ = n;
  for (int i = 0; i < 6; ++i) angular_[i] = isAngularAxis(m.machine.kind, i);
  if (format_ == Format::Gcode) letters_ = gcodeAxisLetters(m.machine);
  values_ = MachineValues{};
  haveMachine_ = true;
  return true;
}

void Reader::comment(const std::string& c, bool first) {
  if (first && startsWith(c, "omnislice ")) {
    // "omnislice <version> <method> <date>"
    std::vector<std::string> parts;
    for (const std::string& p : split(c, ' ')) {
      if (!p.empty()) parts.push_back(p);
    }
    if (parts.size() >= 3) r_.method = parts[2];
    return;
  }
  if (startsWith(c, "omnislice:")) {
    const std::string rest = c.substr(10);
    const size_t sp = rest.find_first_of(" \t");
    const std::string key = rest.substr(0, sp);
    const std::string value = sp == std::string::npos ? "" : trim(rest.substr(sp));
    if (key == "machine") {
      setMachine(value);
    } else if (key == "placement") {
      nlohmann::json j = nlohmann::json::parse(value, nullptr, false);
      if (j.is_discarded() || !j.is_array() || j.size() != 16) {
        return fail(Status::ParseError, "placement must be a JSON array of 16 numbers");
      }
      for (int i = 0; i < 16; ++i) {
        if (!j[i].is_number() || !std::isfinite(j[i].get<double>())) {
          return fail(Status::ParseError,
                      "placement entry " + std::to_string(i) + " is not a finite number");
        }
        r_.placement(i / 4, i % 4) = j[i].get<double>();
      }
    } else if (key == "extrusion") {
      nlohmann::json j = nlohmann::json::parse(value, nullptr, false);
      if (j.is_discarded() || !j.is_object() || !j.contains("mode") || !j["mode"].is_string()) {
        return fail(Status::ParseError, "extrusion header must be {\"mode\":...}");
      }
      const std::string mode = j["mode"].get<std::string>();
      if (mode != "absolute" && mode != "relative") {
        return fail(Status::ParseError, "extrusion mode must be absolute or relative");
      }
      r_.absoluteExtrusion = mode == "absolute";
      relativeE_ = !r_.absoluteExtrusion;
      haveExtrusionMode_ = true;
      if (j.contains("filament_diameter")) {
        const auto& f = j["filament_diameter"];
        if (!f.is_number() || !std::isfinite(f.get<double>()) || f.get<double>() <= 0) {
          return fail(Status::ParseError, "filament_diameter must be a positive number");
        }
        r_.filamentDiameter = f.get<double>();
        haveFilament_ = true;
      }
    } else if (key == "feed") {
      nlohmann::json j = nlohmann::json::parse(value, nullptr, false);
      if (j.is_discarded() || !j.is_object()) {
        return fail(Status::ParseError, "feed header must be a JSON object");
      }
      if (j.contains("semantics")) {
        if (!j["semantics"].is_string()) return fail(Status::ParseError, "feed semantics must be text");
        r_.feedSemantics = j["semantics"].get<std::string>();
      }
    } else if (key == "extruder") {
      nlohmann::json j = nlohmann::json::parse(value, nullptr, false);
      if (j.is_discarded() || !j.is_object() || !j.contains("per_mm_s") ||
          !j["per_mm_s"].is_number() || !std::isfinite(j["per_mm_s"].get<double>()) ||
          j["per_mm_s"].get<double>() <= 0) {
        return fail(Status::ParseError, "extruder header needs a positive per_mm_s");
      }
      analogScale_ = j["per_mm_s"].get<double>();
      if (j.contains("signal")) {
        if (!j["signal"].is_string()) return fail(Status::ParseError, "extruder signal must be a name");
        analogSignal_ = j["signal"].get<std::string>();
      }
      if (j.contains("port")) {
        if (!j["port"].is_number_integer()) return fail(Status::ParseError, "extruder port must be an integer");
        analogPort_ = j["port"].get<int>();
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
      } numerics[] = {{"layer_height", &r_.layerHeight, &haveLayerHeight_},
                      {"line_width", &r_.lineWidth, &haveLineWidth_},
                      {"nozzle_diameter", &r_.nozzleDiameter, &haveNozzle_},
                      {"filament_diameter", &r_.filamentDiameter, &haveFilament_}};
      for (Numeric& num : numerics) {
        if (name != num.name || *num.seen) continue;
        double x = 0;
        if (!parseNumber(v, x) || x <= 0) {
          return fail(Status::ParseError, "setting " + name + " must be a positive number");
        }
        *num.target = x;
        *num.seen = true;
      }
    } else if (key == "layer") {
      if (!parseInt(value, layer_)) return fail(Status::ParseError, "bad layer index");
      layers_.insert(layer_);
    } else if (key == "feature") {
      setFeature(value);
    } else if (key == "part") {
      const std::string idx = value.substr(0, value.find(' '));
      if (!parseInt(idx, part_)) return fail(Status::ParseError, "bad part index");
    }
    // Other omnislice: keys (dialect, end, future additions) carry no replay facts.
    return;
  }
  if (format_ == Format::Csv) {
    std::string cols;
    for (char ch : c) {
      if (!std::isspace(static_cast<unsigned char>(ch))) cols += ch;
    }
    const bool columnLine = cols.size() > 2 && cols[0] == 'q' &&
                            std::isdigit(static_cast<unsigned char>(cols[1])) && cols[2] == ',';
    if (columnLine && cols != "q1,q2,q3,q4,q5,q6,e,f,kind") {
      return fail(Status::UnsupportedFormat, "CSV columns must be q1,q2,q3,q4,q5,q6,e,f,kind");
    }
    return;
  }
  if (startsWith(c, "LAYER:")) {
    if (!parseInt(c.substr(6), layer_)) return fail(Status::ParseError, "bad ;LAYER: index");
    layers_.insert(layer_);
  } else if (c == "LAYER_CHANGE") {
    layer_ = layer_ < 0 ? 0 : layer_ + 1;
    layers_.insert(layer_);
  } else if (startsWith(c, "TYPE:")) {
    setFeature(featureFromType(c.substr(5)));
  } else if (startsWith(c, "Layer height:")) {
    double x = 0;
    if (parseNumber(c.substr(13), x) && x > 0) plainLayerHeight_ = x;
  } else if (startsWith(c, "layer_height =")) {
    double x = 0;
    if (parseNumber(c.substr(14), x) && x > 0 && plainLayerHeight_ == 0) plainLayerHeight_ = x;
  }
}

void Reader::emit(const MachineValues& a, const MachineValues& b, double filament,
                  double feedMmPerMin, double durationS) {
  bool angular = false;
  for (int i = 0; i < n_; ++i) angular = angular || (angular_[i] && a[i] != b[i]);
  if (!angular) {
    // Straight tip path: one piece, no interpolation buffers (the common case of 3-axis moves).
    ProgramMove m;
    Eigen::Vector3d axisA;
    if (!forwardMap(r_.machine, a, m.from, axisA) || !forwardMap(r_.machine, b, m.to, m.axis)) {
      return fail(Status::ParseError, "machine values cannot be mapped to the part frame");
    }
    m.filament = filament;
    m.feedMmPerMin = feedMmPerMin >= 0 ? feedMmPerMin
                     : durationS > 0   ? (m.to - m.from).norm() / durationS * 60.0
                                       : 0.0;
    m.layer = layer_;
    m.part = part_;
    m.feature = feature_;
    m.axes = {b, static_cast<uint8_t>(n_)};
    m.line = lineNo_;
    r_.moves.push_back(std::move(m));
    sawMoves_ = true;
    return;
  }
  // Broken input must not make the replay explode: a move turns at most 10 turns per value
  // (degrees or radians), and the whole program at most kMaxPieces pieces.
  const double turn = r_.machine.kind == MachineKind::Robot6 ? 2 * kPi : 360.0;
  for (int i = 0; i < n_; ++i) {
    if (angular_[i] && std::abs(b[i] - a[i]) > 10 * turn) {
      return fail(Status::ParseError, "a move turns an angular value by more than 10 turns");
    }
  }
  const MoveInterpolation pieces = interpolateMachineMove(r_.machine, a, b);
  if (!pieces.ok()) return fail(Status::ParseError, pieces.message);
  if (r_.moves.size() + pieces.t.size() > kMaxPieces) {
    return fail(Status::ParseError, "the program replays into more than 20 million pieces");
  }
  const double feed = feedMmPerMin >= 0 ? feedMmPerMin
                      : durationS > 0   ? pieces.length / durationS * 60.0
                                        : 0.0;
  for (size_t i = 1; i < pieces.t.size(); ++i) {
    ProgramMove m;
    m.from = pieces.tips[i - 1];
    m.to = pieces.tips[i];
    m.axis = pieces.axes[i];
    m.filament = pieces.t.size() == 2 ? filament : filament * (pieces.t[i] - pieces.t[i - 1]);
    m.feedMmPerMin = feed;
    m.layer = layer_;
    m.part = part_;
    m.feature = feature_;
    m.axes = {lerpValues(a, b, pieces.t[i]), static_cast<uint8_t>(n_)};
    m.line = lineNo_;
    r_.moves.push_back(std::move(m));
  }
  sawMoves_ = true;
}

void Reader::gcodeLine(std::string_view lineText) {
  std::string_view code = lineText.substr(0, lineText.find(';'));
  const size_t paren = code.find('(');
  if (paren != std::string_view::npos) code = code.substr(0, paren);
  code = trimView(code);
  if (code.empty()) return;
  // Line numbers "N123 ... *cs" of host protocols.
  if (code[0] == 'N' || code[0] == 'n') {
    size_t p = 1;
    while (p < code.size() && std::isdigit(static_cast<unsigned char>(code[p]))) ++p;
    code = trimView(code.substr(p));
  }
  const size_t star = code.find('*');
  if (star != std::string_view::npos) code = trimView(code.substr(0, star));
  if (code.empty()) return;
  const char cmdLetter = static_cast<char>(std::toupper(static_cast<unsigned char>(code[0])));
  size_t p = 1;
  while (p < code.size() && (std::isdigit(static_cast<unsigned char>(code[p])) || code[p] == '.')) ++p;
  int cmdNumber = 0;
  if (cmdLetter != 'G' && cmdLetter != 'M') return;  // T0 etc.: nothing to replay
  if (!parseInt(code.substr(1, p - 1), cmdNumber)) return;  // G29.1, M600.1: nothing to replay
  const bool isMove = cmdLetter == 'G' && (cmdNumber == 0 || cmdNumber == 1);
  const bool isG92 = cmdLetter == 'G' && cmdNumber == 92;
  const bool isG28 = cmdLetter == 'G' && cmdNumber == 28;
  if (cmdLetter == 'G' && (cmdNumber == 2 || cmdNumber == 3)) {
    return fail(Status::UnsupportedFormat, "arc moves (G2/G3) are not supported");
  }
  if (cmdLetter == 'G' && cmdNumber == 20) {
    return fail(Status::UnsupportedFormat, "inch units (G20) are not supported");
  }
  if (cmdLetter == 'G' && cmdNumber == 90) relativeAll_ = false;
  if (cmdLetter == 'G' && cmdNumber == 91) relativeAll_ = true;
  if (cmdLetter == 'M' && cmdNumber == 82) relativeE_ = false;
  if (cmdLetter == 'M' && cmdNumber == 83) relativeE_ = true;
  if (!isMove && !isG92 && !isG28) return;

  std::vector<Word>& words = words_;
  words.clear();
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
    double v = 0;
    const size_t used = scanNumber(code.data() + p, code.data() + code.size(), v);
    if (used == 0) {
      if (isG28) {  // "G28 X Y" homes the named axes
        words.push_back({letter, 0.0});
        continue;
      }
      return fail(Status::ParseError, std::string("word ") + letter + " has no number");
    }
    if (!std::isfinite(v)) return fail(Status::ParseError, std::string("word ") + letter + " is not finite");
    p += used;
    words.push_back({letter, v});
  }
  auto axisIndex = [&](char letter) -> int {
    for (size_t i = 0; i < letters_.size(); ++i) {
      if (letters_[i][0] == letter) return static_cast<int>(i);
    }
    return -1;
  };
  if (isG28) {
    // Homing: positions become unknown to a replay; the convention here is 0.
    if (words.empty()) values_ = MachineValues{};
    for (const Word& w : words) {
      const int i = axisIndex(w.letter);
      if (i >= 0) values_[i] = 0.0;
    }
    return;
  }
  if (isG92) {
    if (words.empty()) {
      values_ = MachineValues{};
      e_ = 0;
    }
    for (const Word& w : words) {
      if (w.letter == 'E') e_ = w.value;
      const int i = axisIndex(w.letter);
      if (i >= 0) values_[i] = w.value;
    }
    return;
  }
  // G0 / G1
  MachineValues next = values_;
  double filament = 0;
  bool motionWord = false, eWord = false;
  for (const Word& w : words) {
    if (w.letter == 'F') {
      if (w.value <= 0) return fail(Status::ParseError, "feed F must be positive");
      feed_ = w.value;
      continue;
    }
    if (w.letter == 'E') {
      eWord = true;
      if (relativeAll_ || relativeE_) {
        filament = w.value;
        e_ += w.value;
      } else {
        filament = w.value - e_;
        e_ = w.value;
      }
      continue;
    }
    const int i = axisIndex(w.letter);
    if (i < 0) continue;  // words of axes this kind does not have (e.g. A on cartesian3)
    motionWord = true;
    next[i] = relativeAll_ ? values_[i] + w.value : w.value;
    if (!std::isfinite(next[i])) return fail(Status::ParseError, "axis value is not finite");
  }
  if (!motionWord && !eWord) return;  // feed-only line
  const bool moved = next != values_;
  if (!moved && filament == 0) return;
  if (filament > 0 && !haveExtrusionMode_) {
    // Without a header, the mode of the first extruding move is the program's mode.
    r_.absoluteExtrusion = !(relativeAll_ || relativeE_);
    haveExtrusionMode_ = true;
  }
  emit(values_, next, filament, feed_, 0);
  values_ = next;
}

void Reader::csvRow(const std::string& lineText) {
  if (!haveMachine_) return fail(Status::ParseError, "joint row before the machine header");
  const std::vector<std::string> f = split(lineText, ',');
  if (f.size() != 9) return fail(Status::ParseError, "a joint row has 9 fields q1..q6,e,f,kind");
  MachineValues q{};
  for (int i = 0; i < 6; ++i) {
    if (!parseNumber(f[i], q[i])) return fail(Status::ParseError, "joint q" + std::to_string(i + 1) + " is not a number");
  }
  double e = 0, speed = 0;
  if (!parseNumber(f[6], e)) return fail(Status::ParseError, "e is not a number");
  if (!parseNumber(f[7], speed) || speed < 0) return fail(Status::ParseError, "f must be a number >= 0");
  const std::string kind = trim(f[8]);
  if (kind != "print" && kind != "travel" && kind != "support") {
    return fail(Status::ParseError, "kind must be print, travel or support");
  }
  if (!sawRow_) {
    values_ = q;  // the first row is the start pose
    sawRow_ = true;
  }
  if (q == values_ && e == 0) return;
  emit(values_, q, e, speed * 60.0, 0);
  values_ = q;
}

void Reader::scriptLine(const std::string& lineText) {
  if (startsWith(lineText, "def ")) {
    if (inDef_ || defEnded_) return fail(Status::ParseError, "a second def");
    inDef_ = true;
    return;
  }
  if (lineText == "end") {
    if (!inDef_) return fail(Status::ParseError, "end without def");
    inDef_ = false;
    defEnded_ = true;
    return;
  }
  if (!inDef_) {
    if (defEnded_ && !called_ && lineText.size() > 2 && lineText.compare(lineText.size() - 2, 2, "()") == 0) {
      called_ = true;
      return;
    }
    return fail(Status::ParseError, "statement outside the program definition");
  }
  const size_t open = lineText.find('(');
  if (open == std::string::npos || lineText.back() != ')') {
    return fail(Status::ParseError, "unsupported URScript statement");
  }
  const std::string name = trim(lineText.substr(0, open));
  const std::string args = lineText.substr(open + 1, lineText.size() - open - 2);
  if (!haveMachine_) return fail(Status::ParseError, "statement before the machine header");
  if (name == "movej" || name == "servoj") {
    const size_t lb = args.find('['), rb = args.find(']');
    if (lb == std::string::npos || rb == std::string::npos || rb < lb || trim(args.substr(0, lb)) != "") {
      return fail(Status::ParseError, name + " needs a joint list [q1, ..., q6]");
    }
    const std::vector<std::string> qs = split(args.substr(lb + 1, rb - lb - 1), ',');
    if (qs.size() != 6) return fail(Status::ParseError, name + " needs 6 joint values");
    MachineValues q{};
    for (int i = 0; i < 6; ++i) {
      if (!parseNumber(qs[i], q[i])) return fail(Status::ParseError, "joint value is not a number");
    }
    double t = 0;
    const std::string rest = trim(args.substr(rb + 1));
    if (!rest.empty()) {
      if (rest[0] != ',') return fail(Status::ParseError, "bad arguments after the joint list");
      for (const std::string& a : split(rest.substr(1), ',')) {
        const size_t eq = a.find('=');
        if (eq == std::string::npos) return fail(Status::ParseError, "only named arguments (t=...) are read");
        const std::string key = trim(a.substr(0, eq));
        double v = 0;
        if (!parseNumber(a.substr(eq + 1), v) || v < 0) return fail(Status::ParseError, "argument " + key + " must be a number >= 0");
        if (key == "t") t = v;
      }
    }
    const double filament = analog_ != 0 ? analog_ / analogScale_ * t : 0.0;
    if (analog_ != 0 && t == 0) return fail(Status::ParseError, "extruding move without t");
    if (!sawRow_) {
      sawRow_ = true;
      values_ = q;  // the first target is the start pose (the arm is there when the program runs)
      if (filament == 0) return;
    }
    if (q == values_ && filament == 0) return;
    emit(values_, q, filament, -1, t);
    values_ = q;
    return;
  }
  if (name == "movel" || name == "movec" || name == "movep") {
    return fail(Status::UnsupportedFormat, name + " interpolates in tool space; Omnislice replays joint-space moves (movej, servoj)");
  }
  if (name == "set_analog_out" || name == "set_standard_analog_out") {
    const std::vector<std::string> a = split(args, ',');
    int port = 0;
    double v = 0;
    if (a.size() != 2 || !parseInt(a[0], port) || !parseNumber(a[1], v)) {
      return fail(Status::ParseError, name + "(port, value) expected");
    }
    if (port != analogPort_) return;  // another output
    if (v != 0 && analogScale_ <= 0) return fail(Status::ParseError, "extruder output without an `omnislice:extruder` header");
    analog_ = v;
    return;
  }
  if (name == "sleep") {
    double t = 0;
    if (!parseNumber(args, t) || t < 0) return fail(Status::ParseError, "sleep(t) expects t >= 0");
    const double filament = analog_ != 0 ? analog_ / analogScale_ * t : 0.0;
    if (filament != 0) {
      if (!sawRow_) {
        sawRow_ = true;  // no pose yet: filament at the origin pose of the values
      }
      emit(values_, values_, filament, 0, t);
    }
    return;
  }
  if (name == "textmsg" || name == "popup" || name == "sync") return;
  return fail(Status::ParseError, "unsupported URScript statement '" + name + "'");
}

void Reader::controllerMove(const std::array<double, 6>& deg, double t) {
  MachineValues q{};
  for (int i = 0; i < 6; ++i) q[i] = r_.machine.jointSigns[i] * deg[i] * kPi / 180;
  const double filament = analog_ != 0 ? analog_ / analogScale_ * t : 0.0;
  if (analog_ != 0 && !(t > 0)) return fail(Status::ParseError, "extruding move without a duration");
  if (!sawRow_) {
    sawRow_ = true;
    values_ = q;  // the first target is the start pose
    if (filament == 0) return;
  }
  if (q == values_ && filament == 0) return;
  emit(values_, q, filament, -1, t);
  values_ = q;
}

void Reader::controllerWait(double t) {
  const double filament = analog_ != 0 ? analog_ / analogScale_ * t : 0.0;
  if (filament == 0) return;
  sawRow_ = true;
  emit(values_, values_, filament, 0, t);
}

namespace {
// The six numbers of "a1,a2,...,a6" (RAPID) or "A1 a1, A2 a2, ..., A6 a6" (KRL, any order, E1..E6
// ignored); false when one is missing or not a number.
bool parseAngles(const std::string& text, bool named, std::array<double, 6>& deg) {
  const std::vector<std::string> parts = split(text, ',');
  if (!named) {
    if (parts.size() != 6) return false;
    for (int i = 0; i < 6; ++i) {
      if (!parseNumber(parts[i], deg[i])) return false;
    }
    return true;
  }
  int seen = 0;
  for (const std::string& p : parts) {
    const std::string t = trim(p);
    const size_t sp = t.find(' ');
    if (sp == std::string::npos) return false;
    const std::string name = t.substr(0, sp);
    if (name.size() == 2 && (name[0] == 'A' || name[0] == 'a') && name[1] >= '1' && name[1] <= '6') {
      const int i = name[1] - '1';
      if (!parseNumber(t.substr(sp + 1), deg[i])) return false;
      seen |= 1 << i;
    } else if (!(name.size() == 2 && (name[0] == 'E' || name[0] == 'e'))) {
      return false;
    }
  }
  return seen == 0x3f;
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}
}  // namespace

void Reader::rapidLine(const std::string& lineText) {
  if (moduleEnded_) return fail(Status::ParseError, "text after ENDMODULE");
  const std::string u = upper(lineText);
  if (startsWith(u, "PROC ")) {
    if (inDef_ || defEnded_) return fail(Status::ParseError, "a second PROC");
    inDef_ = true;
    return;
  }
  if (u == "ENDPROC") {
    if (!inDef_) return fail(Status::ParseError, "ENDPROC without PROC");
    inDef_ = false;
    defEnded_ = true;
    return;
  }
  if (u == "ENDMODULE") {
    if (inDef_ || !defEnded_) return fail(Status::ParseError, "ENDMODULE before ENDPROC");
    moduleEnded_ = true;
    return;
  }
  if (!inDef_) return fail(Status::ParseError, "statement outside the PROC");
  if (!haveMachine_) return fail(Status::ParseError, "statement before the machine header");
  if (lineText.back() != ';') return fail(Status::ParseError, "a RAPID statement ends with ';'");
  const std::string stmt = trim(lineText.substr(0, lineText.size() - 1));
  const size_t sp = stmt.find_first_of(" \t");
  const std::string name = upper(stmt.substr(0, sp));
  const std::string args = sp == std::string::npos ? "" : trim(stmt.substr(sp));
  if (name == "MOVEABSJ") {
    const size_t lb = args.find("[["), rb = args.find(']');
    if (lb != 0 || rb == std::string::npos) return fail(Status::ParseError, "MoveAbsJ needs an inline jointtarget [[a1,...,a6],[...]]");
    std::array<double, 6> deg{};
    if (!parseAngles(args.substr(2, rb - 2), false, deg)) return fail(Status::ParseError, "MoveAbsJ needs 6 joint angles");
    const size_t close = args.find("]]", rb);
    if (close == std::string::npos) return fail(Status::ParseError, "MoveAbsJ: unterminated jointtarget");
    const std::vector<std::string> rest = split(args.substr(close + 2), ',');
    if (rest.size() != 4 || !trim(rest[0]).empty()) return fail(Status::ParseError, "MoveAbsJ target, speed, zone, tool expected");
    double t = 0;
    const std::string speed = trim(rest[1]);
    const size_t tArg = upper(speed).find("\\T:=");
    if (tArg != std::string::npos && (!parseNumber(speed.substr(tArg + 4), t) || !(t >= 0))) {
      return fail(Status::ParseError, "MoveAbsJ \\T must be a time >= 0");
    }
    controllerMove(deg, t);
    return;
  }
  if (name == "MOVEL" || name == "MOVEJ" || name == "MOVEC") {
    return fail(Status::UnsupportedFormat, stmt.substr(0, sp) + " moves to a robtarget; Omnislice replays joint targets (MoveAbsJ)");
  }
  if (name == "SETAO") {
    const std::vector<std::string> a = split(args, ',');
    double v = 0;
    if (a.size() != 2 || !parseNumber(a[1], v)) return fail(Status::ParseError, "SetAO signal, value expected");
    if (trim(a[0]) != analogSignal_) return;  // another output
    if (v != 0 && analogScale_ <= 0) return fail(Status::ParseError, "extruder output without an `omnislice:extruder` header");
    analog_ = v;
    return;
  }
  if (name == "WAITTIME") {
    std::string a = args;
    if (startsWith(upper(a), "\\INPOS")) {
      const size_t comma = a.find(',');
      if (comma == std::string::npos) return fail(Status::ParseError, "WaitTime \\InPos, t expected");
      a = a.substr(comma + 1);
    }
    double t = 0;
    if (!parseNumber(a, t) || !(t >= 0)) return fail(Status::ParseError, "WaitTime expects a time >= 0");
    controllerWait(t);
    return;
  }
  if (name == "TPWRITE") return;
  return fail(Status::ParseError, "unsupported RAPID statement '" + stmt.substr(0, sp) + "'");
}

void Reader::krlLine(const std::string& lineText) {
  const std::string u = upper(lineText);
  if (startsWith(u, "DEF ")) {
    if (inDef_ || defEnded_) return fail(Status::ParseError, "a second DEF");
    inDef_ = true;
    return;
  }
  if (u == "END") {
    if (!inDef_) return fail(Status::ParseError, "END without DEF");
    inDef_ = false;
    defEnded_ = true;
    return;
  }
  if (startsWith(u, "&")) return;  // editor attributes (&ACCESS, &REL)
  if (!inDef_) return fail(Status::ParseError, "statement outside DEF ... END");
  if (!haveMachine_) return fail(Status::ParseError, "statement before the machine header");
  auto analogValue = [&](const std::string& assignment) {
    // "$ANOUT[1]=v"
    const size_t eq = assignment.find('=');
    const std::string lhs = upper(trim(assignment.substr(0, eq)));
    double v = 0;
    if (eq == std::string::npos || !parseNumber(assignment.substr(eq + 1), v)) {
      return fail(Status::ParseError, "$ANOUT[n]=value expected");
    }
    if (lhs != "$ANOUT[" + std::to_string(analogPort_) + "]") return;  // another output
    if (v != 0 && analogScale_ <= 0) return fail(Status::ParseError, "extruder output without an `omnislice:extruder` header");
    analog_ = v;
  };
  if (startsWith(u, "PTP ")) {
    const size_t lb = lineText.find('{'), rb = lineText.find('}');
    if (lb == std::string::npos || rb == std::string::npos || rb < lb) return fail(Status::ParseError, "PTP needs an E6AXIS target {A1 ..., A6 ...}");
    std::array<double, 6> deg{};
    if (!parseAngles(lineText.substr(lb + 1, rb - lb - 1), true, deg)) {
      return fail(Status::ParseError, "PTP needs the angles A1 to A6");
    }
    const std::string tail = upper(trim(lineText.substr(rb + 1)));
    if (!tail.empty() && tail != "C_PTP") return fail(Status::ParseError, "unsupported PTP option '" + tail + "'");
    double t = 0;
    if (sawRow_) {
      const MachineValues& q = values_;
      for (int i = 0; i < 6; ++i) {
        const double from = r_.machine.jointSigns[i] * q[i] * 180 / kPi;
        const double speed = r_.machine.jointDynamics[i].velocity * 180 / kPi * percent_ / 100.0;
        if (!(speed > 0)) return fail(Status::ParseError, "KRL replay needs the joint speeds (joint_dynamics) in the machine header");
        t = std::max(t, std::abs(deg[i] - from) / speed);
      }
    }
    controllerMove(deg, t);
    return;
  }
  if (startsWith(u, "LIN ") || startsWith(u, "CIRC ") || startsWith(u, "SLIN ") || startsWith(u, "SPL ")) {
    return fail(Status::UnsupportedFormat, "Cartesian KRL motions are not replayed; Omnislice replays PTP to E6AXIS targets");
  }
  if (startsWith(u, "BAS(")) {
    const size_t comma = lineText.find(','), close = lineText.rfind(')');
    if (comma == std::string::npos || close == std::string::npos || close < comma) return fail(Status::ParseError, "BAS(#..., value) expected");
    const std::string what = upper(trim(lineText.substr(4, comma - 4)));
    if (what == "#VEL_PTP") {
      double p = 0;
      if (!parseNumber(lineText.substr(comma + 1, close - comma - 1), p) || !(p > 0) || p > 100) {
        return fail(Status::ParseError, "BAS(#VEL_PTP, p) needs 0 < p <= 100");
      }
      percent_ = p;
    }
    return;
  }
  if (startsWith(u, "TRIGGER WHEN DISTANCE=0 DELAY=0 DO ")) return analogValue(lineText.substr(35));
  if (startsWith(u, "$ANOUT[")) return analogValue(lineText);
  if (startsWith(u, "WAIT SEC ")) {
    double t = 0;
    if (!parseNumber(lineText.substr(9), t) || !(t >= 0)) return fail(Status::ParseError, "WAIT SEC expects a time >= 0");
    controllerWait(t);
    return;
  }
  if (startsWith(u, "$APO.") || startsWith(u, "$VEL") || startsWith(u, "$ACC")) return;
  return fail(Status::ParseError, "unsupported KRL statement '" + lineText.substr(0, 30) + "'");
}

ParsedProgram Reader::run() {
  if (trimView(text_).empty()) {
    r_.status = Status::EmptyInput;
    r_.message = "program text is empty";
    return r_;
  }
  bool firstContentLine = true;
  size_t pos = 0;
  while (pos <= text_.size() && !failed()) {
    size_t nl = text_.find('\n', pos);
    if (nl == std::string::npos) nl = text_.size();
    const std::string_view lineText = trimView(std::string_view(text_).substr(pos, nl - pos));
    pos = nl + 1;
    ++lineNo_;
    if (lineText.empty()) {
      if (nl == text_.size()) break;
      continue;
    }
    const bool first = firstContentLine;
    firstContentLine = false;
    if (first && startsWith(std::string(lineText.substr(0, 7)), "MODULE ")) {
      // An ABB RAPID module: the header follows as `!` comments.
      format_ = Format::Rapid;
      r_.format = "rapid";
      r_.absoluteExtrusion = false;
      n_ = 6;
      firstContentLine = true;  // the version line is the first comment
      continue;
    }
    if (format_ == Format::Rapid) {
      if (lineText[0] == '!') {
        comment(std::string(trimView(lineText.substr(1))), first);
      } else {
        rapidLine(std::string(lineText));
      }
      continue;
    }
    if (format_ == Format::Krl) {
      if (lineText[0] == ';') {
        comment(std::string(trimView(lineText.substr(1))), first);
      } else {
        krlLine(std::string(lineText));
      }
      continue;
    }
    if (first && lineText[0] == '#') {
      format_ = Format::Csv;  // until a `def` line says URScript
      r_.format = "csv";
      r_.absoluteExtrusion = false;
      n_ = 6;
    }
    if (format_ == Format::Gcode) {
      if (lineText[0] == ';') {
        comment(std::string(trimView(lineText.substr(1))), first);
      } else {
        gcodeLine(lineText);
      }
      continue;
    }
    if (lineText[0] == '#') {
      comment(std::string(trimView(lineText.substr(1))), first);
      continue;
    }
    const std::string line(lineText);
    if (format_ == Format::Csv && !sawRow_ && startsWith(line, "def ")) {
      format_ = Format::UrScript;
      r_.format = "urscript";
    }
    if (format_ == Format::Csv) {
      csvRow(line);
    } else {
      scriptLine(line);
    }
  }
  if (!failed() && format_ == Format::UrScript && (inDef_ || !defEnded_)) {
    fail(Status::ParseError, "URScript program without its closing `end`");
  }
  if (!failed() && format_ == Format::Rapid && (inDef_ || !defEnded_ || !moduleEnded_)) {
    fail(Status::ParseError, "RAPID module without its closing ENDPROC and ENDMODULE");
  }
  if (!failed() && format_ == Format::Krl && (inDef_ || !defEnded_)) {
    fail(Status::ParseError, "KRL program without its closing END");
  }
  if (!failed() && format_ != Format::Gcode && !haveMachine_) {
    fail(Status::ParseError, "robot program without an `omnislice:machine` header");
  }
  if (failed()) {
    ParsedProgram f;
    f.status = status_;
    f.message = message_;
    f.format = r_.format;
    return f;
  }
  if (!haveMachine_) {
    r_.machine = MachineProfile{};  // cartesian3, no declared limits
    if (haveNozzle_) r_.machine.nozzle.diameter = r_.nozzleDiameter;
  }
  if (!haveNozzle_) r_.nozzleDiameter = r_.machine.nozzle.diameter;
  if (!haveLineWidth_) r_.lineWidth = 1.125 * r_.nozzleDiameter;  // usual default width
  if (!haveLayerHeight_) {
    if (plainLayerHeight_ > 0) {
      r_.layerHeight = plainLayerHeight_;
    } else {
      // From the steps between the Z levels of extruding moves (median step).
      std::vector<double> zs;
      for (const ProgramMove& m : r_.moves) {
        if (m.filament > 0 && (m.to - m.from).norm() > 0) zs.push_back(std::round(m.to.z() * 1e4) / 1e4);
      }
      std::sort(zs.begin(), zs.end());
      zs.erase(std::unique(zs.begin(), zs.end()), zs.end());
      std::vector<double> steps;
      for (size_t i = 1; i < zs.size(); ++i) steps.push_back(zs[i] - zs[i - 1]);
      if (!steps.empty()) {
        std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
        r_.layerHeight = steps[steps.size() / 2];
      } else if (!zs.empty() && zs.front() > 0) {
        r_.layerHeight = zs.front();
      }
    }
  }
  r_.layerCount = static_cast<int>(layers_.size());
  if (r_.method.empty()) r_.method = "unknown";
  return std::move(r_);
}

}  // namespace

ParsedProgram readProgram(const std::string& text) { return Reader(text).run(); }

}  // namespace omnislice
