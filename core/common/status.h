// SPDX-License-Identifier: MIT
// One status enum for the whole core. Nothing thrown escapes a core API; results carry a Status
// plus a human message. JS mirrors statusCode() strings (workers/protocol.js).
#pragma once
#include <string>
#include <utility>

namespace omnislice {

enum class Status {
  Ok,
  EmptyInput,          // no bytes, no triangles, nothing to slice
  UnsupportedFormat,   // format not recognised from name or content
  ParseError,          // malformed file content
  TruncatedFile,       // file ends before its declared content
  NonFiniteVertex,     // NaN or infinite coordinate
  DegenerateInput,     // nothing left after dropping degenerate faces, zero-size bbox
  OpenMesh,            // boundary edges: the solid is not closed (cannot slice as a solid)
  NonManifoldInput,    // edges shared by more than two faces
  SelfIntersecting,    // faces intersect each other
  InvalidOption,       // absurd or unknown setting / option
  IoError,             // cannot read or write a file
  Cancelled,           // progress callback asked to stop
  UnsoundProgram,      // the program was made, but simulating it shows it cannot print soundly
                       // (nozzle collisions, tool path left out, unsupported surface, ...);
                       // refused before writing, with why and what would print it
  OutOfMemory,         // a structure the job needs is larger than the memory budget (memory_mb),
                       // refused before allocating it, or an allocation failed
  Internal,            // a bug: an invariant failed
};

// Stable machine-readable code, e.g. Status::OpenMesh -> "open_mesh".
const char* statusCode(Status s);

// Result header shared by every core function result struct.
struct Outcome {
  Status status = Status::Ok;
  std::string message;  // human message, empty when Ok
  bool ok() const { return status == Status::Ok; }
};

// A result of type Result carrying only a status and a message (every core result derives from
// Outcome): `return failed<SliceResult>(Status::InvalidOption, "...")`.
template <typename Result>
Result failed(Status status, std::string message) {
  Result r;
  r.status = status;
  r.message = std::move(message);
  return r;
}

// The same, passing on another step's failure.
template <typename Result>
Result failed(const Outcome& o) {
  return failed<Result>(o.status, o.message);
}

// Something the user should know about a result that is still delivered (e.g. tool path left out
// where the nozzle would hit the part): a stable code and a human message.
struct Warning {
  std::string code;     // e.g. "skipped_tool_path"
  std::string message;  // says what, how much and where
};

}  // namespace omnislice
