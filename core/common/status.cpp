// SPDX-License-Identifier: MIT
#include "common/status.h"

namespace omnislice {

const char* statusCode(Status s) {
  switch (s) {
    case Status::Ok: return "ok";
    case Status::EmptyInput: return "empty_input";
    case Status::UnsupportedFormat: return "unsupported_format";
    case Status::ParseError: return "parse_error";
    case Status::TruncatedFile: return "truncated_file";
    case Status::NonFiniteVertex: return "non_finite_vertex";
    case Status::DegenerateInput: return "degenerate_input";
    case Status::OpenMesh: return "open_mesh";
    case Status::NonManifoldInput: return "non_manifold";
    case Status::SelfIntersecting: return "self_intersecting";
    case Status::InvalidOption: return "invalid_option";
    case Status::IoError: return "io_error";
    case Status::Cancelled: return "cancelled";
    case Status::UnsoundProgram: return "unsound_program";
    case Status::OutOfMemory: return "out_of_memory";
    case Status::Internal: return "internal";
  }
  return "internal";
}

}  // namespace omnislice
