// SPDX-License-Identifier: MIT
// The extrusion model: the filament that deposits a bead of a given section over a length. Used
// by every tool-path (planar layers, curved layers, supports).
#pragma once

namespace omnislice {

// Filament length (mm) that deposits a bead of width w, height h over length L: bead area is a
// rectangle with semicircular ends, (w - h) h + pi h^2 / 4, divided by the filament section; a
// bead narrower than its height (w < h) has its round ends top and bottom: (h - w) w + pi w^2 / 4.
double filamentForBead(double widthMm, double heightMm, double lengthMm, double filamentDiameterMm);

// Paper 003 Eq. 13: the bead an ellipse of width w and height h, (pi / 4) w h L = pi r_m^2 l_m.
double ellipseBeadFilament(double widthMm, double heightMm, double lengthMm, double filamentDiameterMm);

}  // namespace omnislice
