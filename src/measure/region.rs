//! A rectangle of an image's pixels: a ground truth of part of a view (`ocean reference --region`),
//! as exact as one of the whole at the cost of its pixels alone, for the views too large to
//! trace whole (a mark on a 960x540 storm, a short sequence of frames for their change over time).

use crate::error::{Error, Result};

/// Pixels [x, x + width) x [y, y + height) of an image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Region {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl Region {
    /// The whole of a `width` x `height` image.
    pub fn whole(width: u32, height: u32) -> Region {
        Region { x: 0, y: 0, width, height }
    }

    /// Parses `X,Y,W,H` (the command line's `--region`).
    pub fn parse(text: &str) -> std::result::Result<Region, String> {
        let numbers: Vec<&str> = text.split(',').map(str::trim).collect();
        let [x, y, width, height] = numbers[..] else {
            return Err(format!("{text:?} is not X,Y,WIDTH,HEIGHT (four whole numbers of pixels)"));
        };
        let number = |s: &str, what: &str| {
            s.parse::<u32>().map_err(|_| format!("{text:?}: {what} {s:?} is not a whole number of pixels"))
        };
        Ok(Region {
            x: number(x, "X")?,
            y: number(y, "Y")?,
            width: number(width, "WIDTH")?,
            height: number(height, "HEIGHT")?,
        })
    }

    /// Fails, naming `--region`, unless the region is non-empty and inside a `width` x `height`
    /// image.
    pub fn check(&self, width: u32, height: u32) -> Result<()> {
        let inside =
            self.x as u64 + self.width as u64 <= width as u64 && self.y as u64 + self.height as u64 <= height as u64;
        if self.width == 0 || self.height == 0 || !inside {
            return Err(Error::Argument(format!(
                "--region {},{},{},{} is out of range: a non-empty rectangle inside the {width}x{height} image",
                self.x, self.y, self.width, self.height
            )));
        }
        Ok(())
    }

    pub fn pixels(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// The image's pixel (x, y) of the region's pixel `i` (row-major in the region).
    pub fn image_pixel(&self, i: usize) -> (u32, u32) {
        (self.x + (i % self.width as usize) as u32, self.y + (i / self.width as usize) as u32)
    }

    /// The region's pixels of a row-major image `image_width` wide.
    pub fn crop<T: Copy>(&self, image: &[T], image_width: u32) -> Vec<T> {
        (0..self.pixels())
            .map(|i| {
                let (x, y) = self.image_pixel(i);
                image[y as usize * image_width as usize + x as usize]
            })
            .collect()
    }
}

/// "pixels X,Y to X2,Y2" (the first pixel and the one past the last), as the outputs name it.
impl std::fmt::Display for Region {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "pixels {},{} to {},{}", self.x, self.y, self.x + self.width, self.y + self.height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_parse_check_and_crop() {
        let r = Region::parse("2, 1,3,2").unwrap();
        assert_eq!(r, Region { x: 2, y: 1, width: 3, height: 2 });
        for bad in ["1,2,3", "1,2,3,4,5", "a,1,1,1", "1,1,-1,1", ""] {
            assert!(Region::parse(bad).is_err(), "{bad:?}");
        }
        assert!(r.check(5, 3).is_ok());
        for (w, h) in [(4, 3), (5, 2)] {
            let e = r.check(w, h).unwrap_err().to_string();
            assert!(e.contains("--region 2,1,3,2") && e.contains(&format!("{w}x{h}")), "{e}");
        }
        assert!(Region { width: 0, ..r }.check(5, 3).is_err());
        let image: Vec<u32> = (0..15).collect(); // 5 x 3
        assert_eq!(r.crop(&image, 5), vec![7, 8, 9, 12, 13, 14]);
        assert_eq!(r.to_string(), "pixels 2,1 to 5,3");
        assert_eq!(r.image_pixel(4), (3, 2));
    }
}
