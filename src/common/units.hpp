#pragma once
// The one place where the project's numbers change units. Everything inside the library is
// SI (m, s, kg, J, W, rad); files, the command line and figures speak mm, hours, rpm, kW and
// degrees, converted here and nowhere else.
namespace millwear {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kSecondsPerHour = 3600.0;

}  // namespace millwear
