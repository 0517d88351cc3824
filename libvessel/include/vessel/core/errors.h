#pragma once

#include <stdexcept>
#include <string>

namespace vessel {

//! The input (mesh, file, option) is not acceptable; the message says what to fix.
class InvalidInputError : public std::invalid_argument
{
public:
    explicit InvalidInputError(const std::string& what) : std::invalid_argument(what) {}
};

//! The mesh has a topology the requested stage cannot handle (e.g. not a disk).
class TopologyError : public std::runtime_error
{
public:
    explicit TopologyError(const std::string& what) : std::runtime_error(what) {}
};

//! A linear or nonlinear solver failed; the message carries the solver's own report.
class SolverError : public std::runtime_error
{
public:
    explicit SolverError(const std::string& what) : std::runtime_error(what) {}
};

//! Reading or writing a file failed.
class IoError : public std::runtime_error
{
public:
    explicit IoError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace vessel
