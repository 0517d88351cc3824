#pragma once

#include "vessel/io/io.h"

#include <string>

namespace vessel::detail {

//! \brief Read a Geomview OFF file of any header variant: `[ST][C][N][4][n]OFF`, ASCII or
//! `BINARY`.
//!
//! ASCII: `#` comments and blank lines anywhere; the counts `V F [E]` on the header line or the
//! next data line (E is ignored); one vertex per line (x y z, then w for `4OFF`, divided out;
//! normals, colours and texture coordinates are ignored), one face per line (corner count,
//! indices, an optional colour). `nOFF` is read when its dimension is 3.
//! Binary: 32-bit counts, float vertices and int faces, big-endian as Geomview writes them (with
//! a colour count per face) or little-endian as OpenMesh writes them (with or without it); the
//! layout that accounts for every byte of the file is taken.
//! \throw IoError naming the line, vertex or face that is wrong and what was expected.
RawMesh read_off(const std::string& path);

}  // namespace vessel::detail
