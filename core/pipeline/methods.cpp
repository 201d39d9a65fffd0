// SPDX-License-Identifier: MIT
// The method registry: what each method needs before it runs, and its run function.
#include "pipeline/method.h"

namespace omnislice {

namespace {

// Curved-layer methods tilt the nozzle: two rotary axes (a tilting table or head) or a robot.
// head4's nozzle always leans its fixed tilt; its C chooses the azimuth (kinematics.h).
const std::vector<MachineKind> kTilting = {MachineKind::Table5, MachineKind::Head4, MachineKind::Head5,
                                           MachineKind::Robot6};

}  // namespace

const char* methodName(Method method) {
  switch (method) {
    case Method::Planar: return "planar";
    case Method::Multidir: return "multidir";
    case Method::Voxel: return "voxel";
    case Method::Geodesic: return "geodesic";
    case Method::Surface: return "surface";
    case Method::Auto: return "auto";
  }
  return "planar";
}

bool parseMethod(const std::string& name, Method& method) {
  if (name == methodName(Method::Auto)) {
    method = Method::Auto;
    return true;
  }
  for (const MethodEntry& e : methodRegistry()) {
    if (name == methodName(e.method)) {
      method = e.method;
      return true;
    }
  }
  return false;
}

const std::vector<MethodEntry>& methodRegistry() {
  static const std::vector<MethodEntry> registry = {
      {Method::Planar, /*needsSolid=*/true, /*slicesAlongDirection=*/true, /*usesInputTets=*/false,
       /*boundsLayerCount=*/true,
       {MachineKind::Cartesian3, MachineKind::Rotary4, MachineKind::Table5, MachineKind::Head4, MachineKind::Head5,
        MachineKind::Robot6},
       "",
       runPlanarMethod},
      {Method::Multidir, true, false, false, true,
       {MachineKind::Rotary4, MachineKind::Table5, MachineKind::Head4, MachineKind::Head5, MachineKind::Robot6},
       "turns the part (or the nozzle) between parts: choose a machine with a rotary axis or a robot (rotary4, "
       "table5, head5, robot6)",
       runMultidirMethod},
      {Method::Voxel, true, false, false, false, kTilting,
       "tilts the nozzle along curved layers: choose a machine with two rotary axes or a robot (table5, head5, robot6)",
       runVoxelMethod},
      {Method::Geodesic, true, false, true, true, kTilting,
       "tilts the nozzle along curved layers: choose a machine with two rotary axes or a robot (table5, head5, robot6)",
       runGeodesicMethod},
      {Method::Surface, false, false, false, true, kTilting,
       "keeps the nozzle along the surface normal: choose a machine with two rotary axes or a robot (table5, "
       "head5, robot6)",
       runSurfaceMethod},
  };
  return registry;
}

const MethodEntry& methodEntry(Method method) {
  for (const MethodEntry& e : methodRegistry()) {
    if (e.method == method) return e;
  }
  return methodRegistry().front();
}

}  // namespace omnislice
