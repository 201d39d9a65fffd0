// SPDX-License-Identifier: MIT
// The omnislice command line: a thin wrapper over core/pipeline (the same functions the wasm API
// calls). Any bad input or option: exit code 2 and one line `error: <code>: <message>` on stderr;
// a result delivered with warnings: one line `warning: <code>: <message>` each, exit code 0;
// outputs are written to a temporary file and renamed, so no partial file is ever left behind.
#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "common/memory_budget.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "pipeline/pipeline.h"
#include "pipeline/settings.h"
#include "machine/machine.h"
#include "machine/machine_json.h"

namespace {

using namespace omnislice;

const char* kUsage =
    "usage:\n"
    "  omnislice info MESH [--scale S] [--fit-mm MM] [--up AXIS] [--set KEY=VALUE ...]\n"
    "                 [--export-stl OUT.stl]   (also write the placed, repaired mesh)\n"
    "  omnislice slice MESH -o OUT [--method planar|voxel|surface|geodesic|multidir|auto]\n"
    "                 [--fill auto|isoplanar|spiral]\n"
    "                 [--machine NAME] [--machine-file JSON]\n"
    "                 [--gcode-flavor marlin|reprap|klipper] [--robot-format csv|urscript|rapid|krl]\n"
    "                 [--layer-height MM] [--nozzle MM] [--walls N] [--infill PCT]\n"
    "                 [--direction X,Y,Z] [--scale S] [--fit-mm MM] [--up AXIS]\n"
    "                 [--set KEY=VALUE ...] [--report REPORT.json] [--progress]\n"
    "  omnislice verify PROGRAM --mesh MESH [-o REPORT.json] [--memory-mb MB]\n"
    "  omnislice settings            (every setting with its default, as JSON)\n"
    "  omnislice settings --help     (every setting: type, default, range or values, unit, help)\n"
    "  omnislice settings --schema   (the same as JSON, as the page reads it)\n"
    "  omnislice machines            (the built-in machine profiles, as JSON)\n"
    "  omnislice --version | --help\n"
    "Meshes: STL (binary/ASCII), OBJ, OFF, PLY, 3MF; TET (tetrahedral mesh, `N vertices`, `M tets`,\n"
    "coordinates, `4 i j k l`: the solid it fills; --method geodesic uses its tets). AXIS: z, -z,\n"
    "y, -y, x, -x.\n"
    "Machines: cartesian3, rotary4, table5, head4, head5 (G-code), robot6-ur5, robot6-ur5-rated,\n"
    "robot6-irb1200 (ABB), robot6-kr6 (KUKA) (joint CSV, URScript, RAPID or KRL). A profile file\n"
    "(docs/MACHINES.md) overrides --machine.\n"
    "--method surface prints an open surface (a height field) as one layer on a planar base;\n"
    "verify such a program with the same surface as --mesh.\n"
    "--method geodesic (paper 002) meshes the solid into tets (or uses a .tet file's), layers it\n"
    "by the geodesic distance from the platform and prints in the order of geodesic.sequence\n"
    "(a3 | lpt | dpt).\n"
    "--method multidir (paper 000) cuts the solid by planes found by a beam-guided search\n"
    "(multidir.scheme beam | greedy | constrained) into parts printed one after the other with\n"
    "planar layers along their own directions: rotary4 (4dof about its A axis), table5, robot6.\n";

struct CliError {
  Status status;
  std::string message;
};

[[noreturn]] void fail(Status status, const std::string& message) { throw CliError{status, message}; }

std::vector<uint8_t> readFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) fail(Status::IoError, "'" + path + "' is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(Status::IoError, "cannot open '" + path + "'");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), {});
  if (in.bad()) fail(Status::IoError, "cannot read '" + path + "'");
  return bytes;
}

// Write atomically: temp file in the same folder, then rename.
void writeFileAtomic(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp-omnislice";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) fail(Status::IoError, "cannot write '" + path + "'");
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) {
      std::remove(tmp.c_str());
      fail(Status::IoError, "cannot write '" + path + "' (disk full?)");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    fail(Status::IoError, "cannot write '" + path + "'");
  }
}

void check(const Outcome& o) {
  if (!o.ok()) fail(o.status, o.message);
}

// Options shared by the commands: positional arguments plus --flag VALUE pairs.
struct Args {
  std::vector<std::string> positional;
  std::multimap<std::string, std::string> options;
  std::vector<std::string> flags;
  bool has(const std::string& k) const { return options.count(k) > 0; }
  std::string get(const std::string& k) const {
    auto it = options.find(k);
    return it == options.end() ? "" : it->second;
  }
};

Args parseArgs(int argc, char** argv, int first, const std::vector<std::string>& valued,
               const std::vector<std::string>& boolean) {
  Args a;
  for (int i = first; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.size() > 1 && arg[0] == '-') {
      std::string value;
      bool inlineValue = false;
      if (auto eq = arg.find('='); eq != std::string::npos && arg.rfind("--", 0) == 0) {
        value = arg.substr(eq + 1);
        arg = arg.substr(0, eq);
        inlineValue = true;
      }
      if (std::find(boolean.begin(), boolean.end(), arg) != boolean.end()) {
        a.flags.push_back(arg);
        continue;
      }
      if (std::find(valued.begin(), valued.end(), arg) == valued.end()) {
        fail(Status::InvalidOption, "unknown option '" + arg + "'");
      }
      if (!inlineValue) {
        if (i + 1 >= argc) fail(Status::InvalidOption, "option '" + arg + "' needs a value");
        value = argv[++i];
      }
      a.options.emplace(arg, value);
    } else {
      a.positional.push_back(arg);
    }
  }
  return a;
}

// Apply the named CLI options and every --set KEY=VALUE to settings.
void applyOptions(const Args& a, Settings& s) {
  static const std::map<std::string, std::string> named = {
      {"--method", "method"},   {"--machine", "machine"}, {"--layer-height", "layer_height"},
      {"--nozzle", "nozzle_diameter"}, {"--walls", "walls"}, {"--infill", "infill"},
      {"--direction", "direction"}, {"--scale", "scale"}, {"--fit-mm", "fit_mm"}, {"--up", "up"},
      {"--gcode-flavor", "gcode_flavor"}, {"--robot-format", "robot_format"}, {"--fill", "fill"}};
  if (a.has("--machine-file")) {
    const std::vector<uint8_t> bytes = readFile(a.get("--machine-file"));
    check(setSetting(s, "machine_json", std::string(bytes.begin(), bytes.end())));
  }
  for (const auto& [opt, key] : named) {
    auto range = a.options.equal_range(opt);
    for (auto it = range.first; it != range.second; ++it) check(setSetting(s, key, it->second));
  }
  auto range = a.options.equal_range("--set");
  for (auto it = range.first; it != range.second; ++it) {
    const std::string& kv = it->second;
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) {
      fail(Status::InvalidOption, "--set expects KEY=VALUE, got '" + kv + "'");
    }
    check(setSetting(s, kv.substr(0, eq), kv.substr(eq + 1)));
  }
}

// "progress: STAGE P%" on stderr at each stage's start and end, and a line per search level
// ("progress: decompose 37% search level 3: J_G = 1.25 mm^2 (beam, 8 beams)").
ProgressFn stderrProgress(bool enabled) {
  if (!enabled) return {};
  // A stage's end once: several layers of the pipeline may each report a stage's 100 %.
  return [last = std::string(), ended = false](const ProgressEvent& e) mutable {
    if (e.stage != last) ended = false;
    if (e.search) {
      const SearchLevelProgress& s = *e.search;
      std::string line = s.line;
      if (s.beams > 0) line += ", " + std::to_string(s.beams) + (s.beams == 1 ? " beam" : " beams");
      std::fprintf(stderr, "progress: %s %.0f%% search level %d: J_G = %.2f mm^2 (%s)\n", e.stage,
                   100.0 * e.fraction, s.level, s.jgMm2, line.c_str());
    } else if (e.stage != last || (e.fraction >= 1.0 && !ended)) {
      std::fprintf(stderr, "progress: %s %.0f%%\n", e.stage, 100.0 * e.fraction);
      ended = e.fraction >= 1.0;
    }
    last = e.stage;
    return true;
  };
}

// Binary STL of a mesh (float32 coordinates, facet normals from the vertices).
std::string binaryStl(const Mesh& m) {
  std::string out(80, '\0');
  const std::string header = "omnislice placed mesh";
  std::copy(header.begin(), header.end(), out.begin());
  auto put = [&out](const void* p, size_t n) { out.append(static_cast<const char*>(p), n); };
  const uint32_t count = static_cast<uint32_t>(m.faceCount());
  put(&count, 4);
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const Eigen::Vector3d a = m.vertex(m.triangles[3 * f]), b = m.vertex(m.triangles[3 * f + 1]),
                          c = m.vertex(m.triangles[3 * f + 2]);
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    for (const Eigen::Vector3d& v : {n, a, b, c}) {
      const float xyz[3] = {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
      put(xyz, sizeof xyz);
    }
    const uint16_t attributes = 0;
    put(&attributes, 2);
  }
  return out;
}

std::string fileName(const std::string& path) { return std::filesystem::path(path).filename().string(); }

int cmdInfo(int argc, char** argv) {
  Args a = parseArgs(argc, argv, 2, {"--scale", "--fit-mm", "--up", "--set", "--export-stl"}, {});
  if (a.positional.size() != 1) fail(Status::InvalidOption, "info takes one MESH argument");
  Settings s;
  applyOptions(a, s);
  const std::vector<uint8_t> bytes = readFile(a.positional[0]);
  InfoOutput out = runInfo(bytes.data(), bytes.size(), fileName(a.positional[0]), s);
  check(out);
  if (a.has("--export-stl")) writeFileAtomic(a.get("--export-stl"), binaryStl(out.partMesh));
  std::cout << out.infoJson << "\n";
  return 0;
}

int cmdSlice(int argc, char** argv) {
  Args a = parseArgs(argc, argv, 2,
                     {"-o", "--output", "--method", "--fill", "--machine", "--layer-height", "--nozzle",
                      "--walls", "--infill", "--direction", "--scale", "--fit-mm", "--up", "--set",
                      "--report", "--machine-file", "--gcode-flavor", "--robot-format"},
                     {"--progress"});
  if (a.positional.size() != 1) fail(Status::InvalidOption, "slice takes one MESH argument");
  std::string outPath = a.has("-o") ? a.get("-o") : a.get("--output");
  if (outPath.empty()) fail(Status::InvalidOption, "slice needs -o OUT (.gcode, .csv or .script)");
  Settings s;
  applyOptions(a, s);
  const std::vector<uint8_t> bytes = readFile(a.positional[0]);
  const bool progress = std::find(a.flags.begin(), a.flags.end(), "--progress") != a.flags.end();
  SliceOutput out = runSlice(bytes.data(), bytes.size(), fileName(a.positional[0]), s,
                             stderrProgress(progress));
  // A refused (unsound) program: no program is written, but the report says why and where.
  if (out.status == Status::UnsoundProgram && a.has("--report")) {
    writeFileAtomic(a.get("--report"), out.reportJson + "\n");
  }
  check(out);
  writeFileAtomic(outPath, out.program);
  if (a.has("--report")) writeFileAtomic(a.get("--report"), out.reportJson + "\n");
  for (const Warning& w : out.warnings) std::fprintf(stderr, "warning: %s: %s\n", w.code.c_str(), w.message.c_str());
  return 0;
}

int cmdVerify(int argc, char** argv) {
  Args a = parseArgs(argc, argv, 2, {"--mesh", "-o", "--output", "--memory-mb"}, {"--progress"});
  if (a.positional.size() != 1) fail(Status::InvalidOption, "verify takes one PROGRAM argument");
  if (!a.has("--mesh")) fail(Status::InvalidOption, "verify needs --mesh MESH");
  const std::vector<uint8_t> program = readFile(a.positional[0]);
  const std::vector<uint8_t> mesh = readFile(a.get("--mesh"));
  const bool progress = std::find(a.flags.begin(), a.flags.end(), "--progress") != a.flags.end();
  // The memory budget, as setting memory_mb checks it.
  Settings budget;
  if (a.has("--memory-mb")) check(setSetting(budget, "memory_mb", a.get("--memory-mb")));
  VerifyOutput out = runVerify(std::string(program.begin(), program.end()), mesh.data(), mesh.size(),
                               fileName(a.get("--mesh")), stderrProgress(progress), budget.memoryMb);
  check(out);
  const std::string outPath = a.has("-o") ? a.get("-o") : a.get("--output");
  if (!outPath.empty()) writeFileAtomic(outPath, out.verifyJson + "\n");
  std::cout << out.verifyJson << "\n";
  return 0;
}

int cmdMachines() {
  std::cout << "{";
  bool first = true;
  for (const std::string& name : builtinMachineNames()) {
    MachineProfileResult m = builtinMachine(name, Settings{}.bedSize, Settings{}.nozzleDiameter);
    check(m);
    std::cout << (first ? "" : ",") << "\"" << name << "\":" << machineJson(m.machine);
    first = false;
  }
  std::cout << "}\n";
  return 0;
}

int cmdSettings(int argc, char** argv) {
  const Args a = parseArgs(argc, argv, 2, {}, {"--help", "-h", "--schema"});
  if (!a.positional.empty()) fail(Status::InvalidOption, "settings takes no argument");
  const auto has = [&a](const char* f) { return std::find(a.flags.begin(), a.flags.end(), f) != a.flags.end(); };
  if (has("--schema")) {
    std::cout << settingsSchemaJson() << "\n";
    return 0;
  }
  const Settings s;
  if (has("--help") || has("-h")) {
    // One line per setting from the table: key, type, default, range or values, unit; help below.
    for (const SettingSpec& spec : settingSpecs()) {
      std::string what;
      if (spec.type == SettingType::Number || spec.type == SettingType::Integer) {
        what = "[" + formatSettingNumber(spec.min) + ", " + formatSettingNumber(spec.max) + "]";
      } else if (!spec.choices.empty()) {
        for (const std::string& c : spec.choices) what += (what.empty() ? "" : " | ") + c;
      } else {
        what = spec.type == SettingType::Vector ? "x,y,z" : "text";
      }
      if (!spec.unit.empty()) what += " " + spec.unit;
      std::string line = "  " + spec.key + " = " + spec.format(s);
      if (line.size() < 44) line.resize(44, ' ');
      std::cout << line << " " << what;
      if (spec.onlyFor) std::cout << " (method " << methodName(*spec.onlyFor) << ")";
      std::cout << "\n";
      if (!spec.help.empty()) std::cout << "      " << spec.help << "\n";
    }
    return 0;
  }
  std::cout << "{";
  bool first = true;
  for (const auto& [k, v] : listSettings(s)) {
    std::cout << (first ? "" : ",") << "\"" << k << "\":\"" << v << "\"";
    first = false;
  }
  std::cout << "}\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2) {
      std::fputs(kUsage, stderr);
      std::fputs("error: invalid_option: no command given\n", stderr);
      return 2;
    }
    const std::string cmd = argv[1];
    if (cmd == "--help" || cmd == "-h" || cmd == "help") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (cmd == "--version") {
      std::printf("omnislice %s\n", OMNISLICE_VERSION);
      return 0;
    }
    if (cmd == "info") return cmdInfo(argc, argv);
    if (cmd == "slice") return cmdSlice(argc, argv);
    if (cmd == "verify") return cmdVerify(argc, argv);
    if (cmd == "settings") return cmdSettings(argc, argv);
    if (cmd == "machines") return cmdMachines();
    fail(Status::InvalidOption, "unknown command '" + cmd + "' (try --help)");
  } catch (const CliError& e) {
    std::fprintf(stderr, "error: %s: %s\n", statusCode(e.status), e.message.c_str());
    return 2;
  } catch (const std::bad_alloc&) {
    const Outcome o = allocationFailed("running");
    std::fprintf(stderr, "error: %s: %s\n", statusCode(o.status), o.message.c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: internal: %s\n", e.what());
    return 2;
  }
}
