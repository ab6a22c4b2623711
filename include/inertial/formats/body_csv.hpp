/// @file body_csv.hpp
/// The CSV contract for single-body logs (a body on a wrench sensor with a twist sensor), read
/// into a BodyLog (body_effect_model.hpp).
///
/// Contract: a header of comma-separated names, then one sample per non-blank line, as the joint
/// CSV (joint_csv.hpp: LF or CRLF, no quoting, a UTF-8 byte-order mark tolerated, other columns
/// ignored with a notice). Columns, all in the body frame, SI units:
///   t                  time [s], strictly increasing (other units: time_scale below)
///   wx wy wz vx vy vz  twist [rad/s, m/s] (angular velocity, velocity of the frame origin)
///   mx my mz fx fy fz  wrench the sensor applies to the body [N m about the origin, N]
///   gx gy gz           optional: gravity in the body frame [m/s^2] (absent: a free body)
/// Errors name the source, line and column, as the joint CSV's (CsvError).
#pragma once

#include <string>
#include <vector>

#include "inertial/formats/joint_csv.hpp"
#include "inertial/model/body_effect_model.hpp"

namespace inertial {

/// time_scale: seconds per unit of the t column (1e-3 for milliseconds, 1e-9 for nanoseconds;
/// --time-scale), or 0: the stamps must look like seconds. Checked as the joint CSV's
/// (ScaleTimeStamps in joint_csv.hpp).
/// @throws CsvError (cannot open, missing columns, a bad cell, non-increasing time, fewer than 2 rows,
///   time stamps that do not look like seconds); std::invalid_argument if time_scale is negative or
///   not finite.
BodyLog ReadBodyCsv(const std::string& path, std::vector<std::string>* notices = nullptr, double time_scale = 0.0);
BodyLog ParseBodyCsv(std::istream& in, const std::string& source_name, std::vector<std::string>* notices = nullptr,
                     double time_scale = 0.0);

/// Writes the columns above (gravity only when the log has it), %.17g.
/// @throws CsvError if the file cannot be written.
void WriteBodyCsv(const std::string& path, const BodyLog& log);

}  // namespace inertial
