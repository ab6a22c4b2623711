/// @file source_dir.hpp
/// The source tree's absolute path, for programs that read its example files (cmake/source_dir.cpp.in;
/// target inertial_source_dir).
#pragma once

/// The absolute path of the checkout this program was built from, without a trailing slash.
const char* InertialSourceDir();
