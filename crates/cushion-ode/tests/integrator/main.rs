//! The integrator's tests against closed forms and published references, as one test binary
//! (one compile and link of the integrator for all of them).

mod auto_switch;
mod classics;
mod dop853;
mod event_bounds;
mod events;
mod jacobian;
mod kinks;
mod observer;
mod order;
mod rodas_events;
mod rodas_order;
mod rodas_stiff;
mod stiff_contact;
