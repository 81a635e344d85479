//! Classic problems every method is tested against (diffsol's `test_models/` idea): each with
//! its known solution or reference values.

pub mod arenstorf;
pub mod bouncing_ball;
pub mod exponential;
pub mod fading_stiffness;
pub mod hertz_rebound;
pub mod hires;
pub mod kinked_power;
pub mod manufactured;
pub mod orego;
pub mod robertson;
pub mod scheduled_brake;
pub mod van_der_pol;
