// SPDX-License-Identifier: MIT
// The one pi of the core (the literal every file used to repeat; M_PI is not standard C++).
#pragma once

namespace omnislice {

constexpr double kPi = 3.14159265358979323846;

}  // namespace omnislice
