// SPDX-License-Identifier: MIT
// Progress and cancellation: long work takes an optional callback, never a global flag.
#pragma once
#include <cstddef>
#include <functional>
#include <type_traits>
#include <utility>

namespace omnislice {

// A level of a level-by-level search is done. Today the multidir plane search (stage "decompose",
// core/multidir/decomposition.h) reports one per level of each of its lines, then the levels of
// the sequence it returns. All strings are static.
struct SearchLevelProgress {
  const char* line = "";  // "greedy" | "constrained" | "beam": the lines of the search, from the
                          // uncut model each; "screen": a 4dof axis screened by the constrained
                          // line on a coarse grid (it only ranks the axes); "chosen": the returned
                          // sequence, after refinement, reported once at the end
  int level = 0;          // planes in the line's sequences at this level; 0 = the uncut model
  double jgMm2 = 0;       // mm^2, >= 0. Search lines: the least J_G the line reached with at most
                          // `level` planes (nonincreasing along a line). "chosen": J_G after the
                          // first `level` planes, exact (= MultidirStats::jgPerLevel[level])
  int beams = 0;          // sequences the line goes on extending after this level (0 = it ends)
};

// One progress report.
struct ProgressEvent {
  const char* stage = "";                    // "read", "validate", "slice", "toolpath", "decompose", ...
  double fraction = 0;                       // of the stage done, in [0, 1]
  const SearchLevelProgress* search = nullptr;  // a search level is done; null = plain report.
                                                // Valid during the call only
};

// The progress callback: called with each report; returns false to cancel: the callee then stops
// soon (within a few milliseconds of work) and returns Status::Cancelled. An empty callback means
// "no progress, never cancel". Made from any callable taking (const ProgressEvent&), or taking
// (const char* stage, double fraction) when the detail is not needed; either returns bool.
class ProgressFn {
 public:
  ProgressFn() = default;
  ProgressFn(std::nullptr_t) {}

  template <class F, std::enable_if_t<!std::is_same_v<std::decay_t<F>, ProgressFn> &&
                                          std::is_invocable_r_v<bool, F&, const ProgressEvent&>,
                                      int> = 0>
  ProgressFn(F f) : fn_(std::move(f)) {}

  template <class F, std::enable_if_t<!std::is_same_v<std::decay_t<F>, ProgressFn> &&
                                          !std::is_invocable_r_v<bool, F&, const ProgressEvent&> &&
                                          std::is_invocable_r_v<bool, F&, const char*, double>,
                                      int> = 0>
  ProgressFn(F f)
      : fn_([f = std::move(f)](const ProgressEvent& e) mutable { return f(e.stage, e.fraction); }) {}

  explicit operator bool() const { return static_cast<bool>(fn_); }
  bool operator()(const ProgressEvent& e) const { return fn_(e); }

 private:
  std::function<bool(const ProgressEvent&)> fn_;
};

// Helper: call fn if set; true means continue.
inline bool reportProgress(const ProgressFn& fn, const char* stage, double fraction) {
  return !fn || fn(ProgressEvent{stage, fraction, nullptr});
}

// The same with a finished search level.
inline bool reportProgress(const ProgressFn& fn, const char* stage, double fraction,
                           const SearchLevelProgress& search) {
  return !fn || fn(ProgressEvent{stage, fraction, &search});
}

}  // namespace omnislice
