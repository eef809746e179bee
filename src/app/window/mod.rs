//! The window: `ocean view`. winit gives the window and its events; the loop is ours (events
//! pumped between frames), so that the GPU context and the renderer, which borrow each other,
//! live on the loop's stack and drop in order. `presenter` makes the window a render target of
//! the same frame as `ocean render`; `controls` maps keys and the mouse; `script` runs the
//! automation flags; `stats` measures without adding waits.

pub mod controls;
pub mod presenter;
pub mod script;
pub mod stats;
pub mod view;

use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::ActiveEventLoop;
use winit::window::{Window, WindowAttributes, WindowId};

/// Collects the window's events between frames; makes the window when the loop first resumes.
pub struct Events {
    attributes: WindowAttributes,
    pub window: Option<Window>,
    pub failed: Option<String>,
    pub queue: Vec<WindowEvent>,
}

impl Events {
    pub fn new(attributes: WindowAttributes) -> Events {
        Events { attributes, window: None, failed: None, queue: Vec::new() }
    }
}

impl ApplicationHandler for Events {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none() && self.failed.is_none() {
            match event_loop.create_window(self.attributes.clone()) {
                Ok(window) => self.window = Some(window),
                Err(e) => self.failed = Some(e.to_string()),
            }
        }
    }

    fn window_event(&mut self, _event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        self.queue.push(event);
    }
}
