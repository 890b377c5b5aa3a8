#pragma once
// The one place where the project's numbers change units. Everything inside the library is
// SI (m, s, kg, J, W, rad); files, the command line and figures speak mm, hours, rpm, kW and
// degrees, converted here and nowhere else.
namespace millwear {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kSecondsPerHour = 3600.0;
inline constexpr double kGravity = 9.81;  // m/s^2

// Angles and speeds as files and the terminal give them.
inline constexpr double rad_from_deg(double deg) { return deg * (kPi / 180.0); }
inline constexpr double deg_from_rad(double rad) { return rad / (kPi / 180.0); }
inline constexpr double rpm_from_rad_s(double rad_s) { return rad_s * 60.0 / (2.0 * kPi); }

// Lengths, areas and powers as files and the terminal give them: a length in mm times kMm is
// in m, an area in mm^2 times kMm2 in m^2.
inline constexpr double kMm = 1e-3;
inline constexpr double kMm2 = 1e-6;
inline constexpr double in_mm(double m) { return m * 1e3; }
inline constexpr double in_mm2(double m2) { return m2 * 1e6; }
inline constexpr double in_kW(double W) { return W / 1e3; }
inline constexpr double watts_from_kW(double kW) { return kW * 1e3; }

// A rate per second as a rate per operating hour.
inline constexpr double per_hour(double per_second) { return per_second * kSecondsPerHour; }
// m per second -> mm per 1000 operating hours (the liner's colour scale).
inline constexpr double mm_per_1000h(double m_per_s) { return per_hour(m_per_s) * 1e6; }
// Liner metal lost per energy the mill draws: kg/J -> g/kWh (the figure plants report).
inline constexpr double g_per_kWh(double kg_per_J) { return kg_per_J * 1e3 * 3.6e6; }
// Specific power: W/kg -> kW per tonne of charge (the same number).
inline constexpr double kW_per_t(double W_per_kg) { return W_per_kg; }

}  // namespace millwear
