//! Where each primitive can matter, as the two balls the tile passes test
//! (templates/fields/scene_tiles.wgsl): its ABV's bounding ball, and a
//! *limit* ball its intersection ancestors allow.
//!
//! An intersection is never below either operand (sharp, compact smooth and
//! the joins alike: `f ≥ max(a, b)`), and a difference never below its left
//! operand. So where an intersection's other operand is beyond its range of
//! interest, so is the intersection, and nothing under it decides the root
//! there: a primitive under the right operand of an intersection matters
//! only inside the bound of the left one, and the other way round, and a
//! primitive under a difference's right operand only inside the bound of
//! its left one. Outside the limit the primitive can be left out of a
//! tile's view exactly as outside its own ABV (the sparse traversal then
//! drops the intersection), so a tile lists it only where both balls meet
//! its frustum, and the GPU takes the smaller of the two balls and the
//! ball around their lens there, each widened by the termination width
//! first (widening after intersecting would not hold a thin lens's near
//! misses). For Zanni's sphere pairs the limit of each sphere is the
//! other, and a pair's ball shrinks to its lens.
//!
//! A subtree's bound here is one ball holding {f ≤ r⁺} of that subtree
//! (its range of interest): a union's encloses both operands', an
//! intersection's is the smaller operand's and a difference's its left
//! one's. Both steps hold for balls widened alike, which the lens step
//! would not, so the lens is taken on the GPU only. Unary nodes bound
//! nothing (an offset moves the surface beyond its operand's ball).

use super::linear::{Linear, NODE_TYPE_SHIFT, OFFSET, UNION};
use super::roi::Abv;
use glam::DVec3;

/// A ball in f64; an infinite radius holds everything.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Ball {
    c: DVec3,
    r: f64,
}

const ALL: Ball = Ball { c: DVec3::ZERO, r: f64::INFINITY };

impl Ball {
    /// The smaller of two balls that both hold a region.
    fn smaller(self, o: Ball) -> Ball {
        if o.r < self.r {
            o
        } else {
            self
        }
    }

    /// The smallest ball holding both.
    fn enclose(self, o: Ball) -> Ball {
        if !(self.r.is_finite() && o.r.is_finite()) {
            return ALL;
        }
        let d = (o.c - self.c).length();
        if d + o.r <= self.r {
            return self;
        }
        if d + self.r <= o.r {
            return o;
        }
        let r = 0.5 * (d + self.r + o.r);
        Ball { c: self.c + (o.c - self.c) * ((r - self.r) / d), r }
    }

    /// As the GPU reads it: rounded outward to f32.
    fn to_f32(self) -> [f32; 4] {
        if !self.r.is_finite() {
            return [0.0, 0.0, 0.0, f32::INFINITY];
        }
        // The centre's rounding moves it by up to 2⁻²⁴ of its coordinates.
        let r = (self.r + self.c.abs().max_element() * 1e-6) as f32;
        [self.c.x as f32, self.c.y as f32, self.c.z as f32, r.next_up() * (1.0 + 1e-6)]
    }
}

/// The bounding ball of an ABV (what `rows::ball` rounds to f32).
fn abv_ball(a: &Abv) -> Ball {
    match *a {
        Abv::Always => ALL,
        Abv::Sphere { centre, radius } => Ball { c: centre.into(), r: radius },
        Abv::Box { centre, half, .. } => Ball { c: centre.into(), r: DVec3::from(half).length() },
        Abv::Capsule { a, b, radius } => {
            let (a, b) = (DVec3::from(a), DVec3::from(b));
            Ball { c: 0.5 * (a + b), r: 0.5 * (b - a).length() + radius }
        }
    }
}

/// What kind of node `k` is, from its node word.
enum Kind {
    Leaf,
    Unary,
    /// Binary: 0 union, 1 intersection, 2 difference (codes come three a
    /// style from NODE_UNION).
    Binary(u32),
}

impl Linear {
    fn kind(&self, k: usize) -> Kind {
        let ty = (self.nodes[k][0] >> NODE_TYPE_SHIFT) & 0xff;
        if self.is_leaf(k as u32) {
            Kind::Leaf
        } else if ty >= OFFSET {
            Kind::Unary
        } else {
            Kind::Binary((ty - UNION) % 3)
        }
    }

    /// Whether node `k`'s bound is part of another primitive's limit: an
    /// intersection above it, or a difference above it with `k` in its
    /// left operand.
    pub fn bounds_a_limit(&self, k: usize) -> bool {
        let n = self.nodes.len();
        let mut c = k;
        while (self.parent[c] as usize) < n {
            let p = self.parent[c] as usize;
            match self.kind(p) {
                Kind::Binary(1) => return true,
                Kind::Binary(2) if self.children[p][0] as usize == c => return true,
                _ => {}
            }
            c = p;
        }
        false
    }

    /// Each primitive's limit ball (module doc), in `primitives` order, as
    /// the GPU reads it (an infinite radius: no limit).
    pub fn limit_balls(&self) -> Vec<[f32; 4]> {
        let n = self.nodes.len();
        let mut bound = vec![ALL; n];
        let mut prim = 0;
        // Post-order: operands before their operator.
        for k in 0..n {
            let [l, r] = self.children[k].map(|c| c as usize);
            bound[k] = match self.kind(k) {
                Kind::Leaf => {
                    prim += 1;
                    abv_ball(&self.abvs[prim - 1])
                }
                Kind::Unary => ALL,
                Kind::Binary(0) => bound[l].enclose(bound[r]),
                Kind::Binary(1) => bound[l].smaller(bound[r]),
                Kind::Binary(_) => bound[l],
            };
        }
        let mut limit = vec![ALL; n];
        // Reversed: an operator before its operands.
        for k in (0..n).rev() {
            let [l, r] = self.children[k].map(|c| c as usize);
            let c = limit[k];
            match self.kind(k) {
                Kind::Leaf => {}
                Kind::Unary => limit[l] = c,
                Kind::Binary(0) => (limit[l], limit[r]) = (c, c),
                Kind::Binary(1) => (limit[l], limit[r]) = (c.smaller(bound[r]), c.smaller(bound[l])),
                Kind::Binary(_) => (limit[l], limit[r]) = (c, c.smaller(bound[l])),
            }
        }
        self.primitives.iter().map(|&k| limit[k as usize].to_f32()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enclosing_balls_hold_both_and_keep_a_ball_that_holds_the_other() {
        let a = Ball { c: DVec3::ZERO, r: 1.0 };
        let b = Ball { c: DVec3::new(3.0, 0.0, 0.0), r: 1.0 };
        assert_eq!(a.enclose(b), Ball { c: DVec3::new(1.5, 0.0, 0.0), r: 2.5 });
        let inner = Ball { c: DVec3::new(0.5, 0.0, 0.0), r: 0.25 };
        assert_eq!(a.enclose(inner), a);
        assert_eq!(inner.enclose(a), a);
        assert_eq!(a.enclose(ALL).r, f64::INFINITY);
        assert_eq!(a.smaller(inner), inner);
        assert_eq!(ALL.smaller(a), a);
    }
}
