#pragma once
// A small valid scene (a 0.6 m mill turning one way, a ball size and two rock sizes) and the
// lifter profile it names ("lifter.toml"), for the scene and override tests to change one
// thing in.
namespace millwear::testing {

inline constexpr const char* kTinyScene = R"(name = "tiny"
[mill]
diameter = 0.6
length = 0.3
speed = 0.75
direction = "forward"
[lifters]
rows = 12
profile = "lifter.toml"
[charge]
filling = 0.3
ball_filling = 0.1
[[charge.species]]
name = "ball"
ball = true
density = 7800.0
sizes = [20.0]
mass_fractions = [1.0]
[[charge.species]]
name = "rock"
density = 2700.0
sizes = [10.0, 20.0]
mass_fractions = [0.4, 0.6]
[solver]
seed = 3
[wear]
wear_rate = 1e-11
replacement_height = 5.0
)";

inline constexpr const char* kTinyLifter = R"(name = "small"
form = "trapezoid"
height = 20.0
top_width = 10.0
leading_face_angle = 30.0
trailing_face_angle = 30.0
)";

}  // namespace millwear::testing
