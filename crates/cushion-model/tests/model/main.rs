//! The model's tests: whole runs against closed forms and independent references, the scene
//! keys and their documentation, as one test binary (one compile and link of the model).

mod common;

mod auto;
mod compressible;
mod config;
mod dop853_at_rest;
mod early_end;
mod event_bounds;
mod friction_and_contacts;
mod peaks;
mod properties;
mod recurring_events;
mod runs;
mod scene_keys_doc;
mod statuses;
mod tolerance;
