//! Keyboard and mouse: what each key does to the scene, the camera's motion from held keys, and
//! the help text (`H`, and the README's table).

use crate::embed::Method;
use crate::model::scene::{wrap_degrees, Scene};
use crate::model::scene::{Ev100, Exposure};
use std::collections::HashSet;
use winit::event::{ElementState, MouseButton, MouseScrollDelta};
use winit::keyboard::KeyCode;

pub const HELP: &str = "\
controls:
  mouse drag (left)   look around (yaw, pitch)
  W A S D             move over the sea
  Q E, mouse wheel    eye height (never below the water under the eye)
  [ ]                 sun elevation -/+ 1 degree
  , .                 sun azimuth -/+ 5 degrees
  - =                 exposure -/+ a quarter stop
  space               pause / resume time
  1 2 3 4             method: full (ours), constant BRDF, no filtering, the paper as published
  F12                 screenshot (PNG of what is shown); Shift+F12: EXR of the linear radiance
  R                   reload the scene file (also on save)
  H                   this help
  Escape              quit";

/// Lowest eye the controls allow above the water under the eye (m): the extreme scenes' 5 cm.
pub const MIN_HEIGHT_M: f64 = 0.05;
/// Degrees of yaw or pitch per pixel of mouse drag.
const DEGREES_PER_PIXEL: f64 = 0.15;
/// Pitch stays short of straight up or down, where yaw stops meaning anything.
const MAX_PITCH_DEG: f64 = 89.5;

/// What a key press asks of the viewer beyond changing the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    Quit,
    Help,
    Reload,
    TogglePause,
    Screenshot {
        radiance: bool,
    },
    Method(Method),
    /// The sun, sky or exposure changed (logged).
    SceneChanged,
}

#[derive(Default)]
pub struct Controls {
    held: HashSet<KeyCode>,
    shift: bool,
    dragging: bool,
    cursor: Option<(f64, f64)>,
}

impl Controls {
    pub fn set_shift(&mut self, shift: bool) {
        self.shift = shift;
    }

    /// A key went down or up; returns what a press asks for. Scene keys change `scene` directly.
    pub fn key(&mut self, code: KeyCode, state: ElementState, scene: &mut Scene) -> Option<Action> {
        if state == ElementState::Released {
            self.held.remove(&code);
            return None;
        }
        self.held.insert(code);
        let sun = &mut scene.sun;
        let render = &mut scene.render;
        let changed = Some(Action::SceneChanged);
        match code {
            KeyCode::Escape => Some(Action::Quit),
            KeyCode::KeyH => Some(Action::Help),
            KeyCode::KeyR => Some(Action::Reload),
            KeyCode::Space => Some(Action::TogglePause),
            KeyCode::F12 => Some(Action::Screenshot { radiance: self.shift }),
            KeyCode::Digit1 => Some(Action::Method(Method::Full)),
            KeyCode::Digit2 => Some(Action::Method(Method::ConstantBrdf)),
            KeyCode::Digit3 => Some(Action::Method(Method::NoFilter)),
            KeyCode::Digit4 => Some(Action::Method(Method::Paper)),
            KeyCode::BracketLeft | KeyCode::BracketRight => {
                let step = if code == KeyCode::BracketLeft { -1.0 } else { 1.0 };
                sun.elevation_deg = (sun.elevation_deg + step).clamp(-90.0, 90.0);
                changed
            }
            KeyCode::Comma | KeyCode::Period => {
                let step = if code == KeyCode::Comma { -5.0 } else { 5.0 };
                sun.azimuth_deg = wrap_degrees(sun.azimuth_deg + step);
                changed
            }
            KeyCode::Minus | KeyCode::Equal => {
                let stops = if code == KeyCode::Minus { -0.25 } else { 0.25 };
                // A stop brighter is one EV lower; automatic exposure has nothing to set.
                match (render.ev100, render.exposure()) {
                    (Some(Ev100::Auto), _) => return None,
                    (Some(Ev100::Value(ev)), _) => render.ev100 = Some(Ev100::Value((ev - stops).clamp(-10.0, 30.0))),
                    (None, Exposure::PerKcd(e)) => render.exposure = Some((e * 2f64.powf(stops)).clamp(1e-4, 1e4)),
                    (None, Exposure::Auto) => return None,
                }
                changed
            }
            _ => None,
        }
    }

    pub fn mouse_button(&mut self, button: MouseButton, state: ElementState) {
        if button == MouseButton::Left {
            self.dragging = state == ElementState::Pressed;
        }
    }

    /// The cursor moved: a drag turns the camera.
    pub fn cursor(&mut self, x: f64, y: f64, scene: &mut Scene) {
        if let (true, Some((px, py))) = (self.dragging, self.cursor) {
            let camera = &mut scene.camera;
            camera.yaw_deg = wrap_degrees(camera.yaw_deg - (x - px) * DEGREES_PER_PIXEL);
            camera.pitch_deg = (camera.pitch_deg - (y - py) * DEGREES_PER_PIXEL).clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG);
        }
        self.cursor = Some((x, y));
    }

    /// The wheel: each notch (or 40 pixels of a touchpad) is a tenth of a doubling of height.
    pub fn wheel(&mut self, delta: MouseScrollDelta, scene: &mut Scene) {
        let notches = match delta {
            MouseScrollDelta::LineDelta(_, y) => y as f64,
            MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
        };
        scale_height(scene, 2f64.powf(-0.1 * notches));
    }

    /// Moves the eye for `dt` seconds of held keys: a ground speed of one eye height per second
    /// (at least 2 m/s), and height doubling or halving per second.
    pub fn update(&self, scene: &mut Scene, dt: f64) {
        let camera = &mut scene.camera;
        let yaw = camera.yaw_deg.to_radians();
        let (forward, right) = ([yaw.cos(), yaw.sin()], [yaw.sin(), -yaw.cos()]);
        let axis = |plus: KeyCode, minus: KeyCode| {
            self.held.contains(&plus) as i32 as f64 - self.held.contains(&minus) as i32 as f64
        };
        let (ahead, aside) = (axis(KeyCode::KeyW, KeyCode::KeyS), axis(KeyCode::KeyD, KeyCode::KeyA));
        let speed = camera.height_m.max(2.0) * dt;
        camera.x_m = (camera.x_m + speed * (ahead * forward[0] + aside * right[0])).clamp(-1e7, 1e7);
        camera.y_m = (camera.y_m + speed * (ahead * forward[1] + aside * right[1])).clamp(-1e7, 1e7);
        let up = axis(KeyCode::KeyE, KeyCode::KeyQ);
        if up != 0.0 {
            scale_height(scene, 2f64.powf(up * dt));
        }
    }
}

fn scale_height(scene: &mut Scene, factor: f64) {
    // The scene's own limits: above MIN_HEIGHT_M (the water under the eye is accounted for by
    // the frame), at most the 100 km the scene format allows.
    scene.camera.height_m = (scene.camera.height_m * factor).clamp(MIN_HEIGHT_M, 100_000.0);
}
