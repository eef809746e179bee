//! The automation flags of `ocean view`: scripted resizes and minimizes at given frames, parsed
//! with one-line errors, so that a window session can be tested without a person at the keyboard.

/// `--resize-at FRAME:WxH`: ask the window for WxH after FRAME presented frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ResizeAt {
    pub frame: u64,
    pub width: u32,
    pub height: u32,
}

/// `--minimize-at FRAME:TICKS`: minimize after FRAME presented frames and restore TICKS frame
/// periods (1/60 s each: nothing is presented while minimized) later.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MinimizeAt {
    pub frame: u64,
    pub ticks: u32,
}

/// Largest window side a script may ask for (Vulkan 1.3 guarantees 4096 for images).
pub const MAX_SIDE: u32 = 16384;

fn split(text: &str, what: &str) -> Result<(u64, String), String> {
    let (frame, rest) = text.split_once(':').ok_or_else(|| format!("{text:?}: expected {what}"))?;
    let frame = frame.trim().parse::<u64>().map_err(|_| format!("{text:?}: FRAME must be a whole number >= 0"))?;
    Ok((frame, rest.trim().to_owned()))
}

pub fn parse_resize(text: &str) -> Result<ResizeAt, String> {
    let (frame, size) = split(text, "FRAME:WIDTHxHEIGHT, e.g. 10:640x360")?;
    let (w, h) = size.split_once(['x', 'X']).ok_or_else(|| format!("{text:?}: expected FRAME:WIDTHxHEIGHT"))?;
    let side = |s: &str| {
        s.trim()
            .parse::<u32>()
            .ok()
            .filter(|v| (1..=MAX_SIDE).contains(v))
            .ok_or_else(|| format!("{text:?}: width and height must be whole numbers in [1, {MAX_SIDE}]"))
    };
    Ok(ResizeAt { frame, width: side(w)?, height: side(h)? })
}

pub fn parse_minimize(text: &str) -> Result<MinimizeAt, String> {
    let (frame, ticks) = split(text, "FRAME:FRAMES, e.g. 20:5")?;
    let ticks = ticks
        .parse::<u32>()
        .ok()
        .filter(|t| (1..=3600).contains(t))
        .ok_or_else(|| format!("{text:?}: FRAMES (how long to stay minimized) must be in [1, 3600]"))?;
    Ok(MinimizeAt { frame, ticks })
}

/// What the script asks for now.
#[derive(Debug, PartialEq, Eq)]
pub enum Step {
    Resize(u32, u32),
    Minimize,
    Restore,
}

/// The scripted steps in frame order.
pub struct Script {
    resizes: Vec<ResizeAt>,
    minimizes: Vec<MinimizeAt>,
    /// Ticks left before restoring, while minimized by the script.
    restore_in: Option<u32>,
}

impl Script {
    pub fn new(mut resizes: Vec<ResizeAt>, mut minimizes: Vec<MinimizeAt>) -> Script {
        resizes.sort_by_key(|r| std::cmp::Reverse(r.frame));
        minimizes.sort_by_key(|m| std::cmp::Reverse(m.frame));
        Script { resizes, minimizes, restore_in: None }
    }

    /// Steps due after `frame` presented frames (called once per loop turn).
    pub fn due(&mut self, frame: u64) -> Vec<Step> {
        let mut steps = Vec::new();
        while self.resizes.last().is_some_and(|r| r.frame <= frame) {
            let r = self.resizes.pop().expect("checked");
            steps.push(Step::Resize(r.width, r.height));
        }
        if self.restore_in.is_none() && self.minimizes.last().is_some_and(|m| m.frame <= frame) {
            let m = self.minimizes.pop().expect("checked");
            self.restore_in = Some(m.ticks);
            steps.push(Step::Minimize);
        }
        steps
    }

    /// One frame period passed while minimized; Some(Restore) when the window should come back.
    pub fn tick_minimized(&mut self) -> Option<Step> {
        let left = self.restore_in.as_mut()?;
        *left = left.saturating_sub(1);
        (*left == 0).then(|| {
            self.restore_in = None;
            Step::Restore
        })
    }

    pub fn minimized_by_script(&self) -> bool {
        self.restore_in.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_rejects() {
        assert_eq!(parse_resize("10:640x360"), Ok(ResizeAt { frame: 10, width: 640, height: 360 }));
        assert!(parse_resize("10:0x360").unwrap_err().contains("[1, 16384]"));
        assert!(parse_resize("ten:640x360").unwrap_err().contains("FRAME"));
        assert!(parse_resize("640x360").unwrap_err().contains("FRAME:"));
        assert_eq!(parse_minimize("20:5"), Ok(MinimizeAt { frame: 20, ticks: 5 }));
        assert!(parse_minimize("20:0").is_err());
        assert!(parse_minimize("20").is_err());
    }

    #[test]
    fn steps_come_in_order_and_restore_after_the_ticks() {
        let mut s =
            Script::new(vec![ResizeAt { frame: 5, width: 8, height: 8 }], vec![MinimizeAt { frame: 3, ticks: 2 }]);
        assert!(s.due(2).is_empty());
        assert_eq!(s.due(3), vec![Step::Minimize]);
        assert_eq!(s.tick_minimized(), None);
        assert_eq!(s.tick_minimized(), Some(Step::Restore));
        assert_eq!(s.due(6), vec![Step::Resize(8, 8)]);
    }
}
