#pragma once

#include "vessel/pipeline.h"

#include <string>
#include <vector>

namespace vessel::cli {

//! `--viewpoint`'s words into \p options: `X Y Z` (FarSideEndpoints and
//! CostOptions::viewpoint from that point) or `face-on` (CostOptions::face_on); none leaves
//! them as they are.
//! \throw InvalidInputError naming what to give instead.
void apply_viewpoint(const std::vector<std::string>& words, FlattenOptions& options);

//! \p word quoted for a POSIX shell when it needs it (spaces, quotes, $ ...), else unchanged.
std::string shell_quote(const std::string& word);

//! The command line \p argv as one shell-quoted string, without any `--viewpoint X Y Z` or
//! `--viewpoint face-on` (the viewer page appends the viewpoint of its camera). argv[0] is
//! replaced by \p program.
std::string command_without_viewpoint(const std::string& program, int argc, char** argv);

//! \p words shell-quoted and joined with spaces.
std::string join_quoted(const std::vector<std::string>& words);

}  // namespace vessel::cli
