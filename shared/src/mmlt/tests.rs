use glam::Vec3;

use super::*;

#[test]
fn techniques_cover_all_splits() {
    for depth in 0..10 {
        let n = depth + 2;
        let mut seen = vec![false; n as usize];
        for i in 0..1000 {
            let (s, t) = technique(i as f32 / 1000.0, depth);
            assert_eq!(s + t, n);
            assert!(t >= 1);
            seen[s as usize] = true;
        }
        assert!(seen.iter().all(|x| *x));
        assert_eq!(technique(0.999_999_9, depth).0, n - 1);
    }
}

#[test]
fn dimensions_and_slots_do_not_overlap() {
    for k in 0..12 {
        let dims = sample_dimensions(k);
        let mut used = vec![false; dims as usize];
        let mut mark = |d: u32| {
            assert!(d < dims);
            assert!(!used[d as usize], "dimension {d} used twice at max depth {k}");
            used[d as usize] = true;
        };
        for d in 0..DIM_BOUNCES {
            mark(d);
        }
        for side in 0..2 {
            for b in 0..k {
                mark(bounce_dimension(side, b, k));
                mark(bounce_dimension(side, b, k) + 1);
            }
        }
        // Camera vertices 0..t and light vertices 0..s with s + t = depth + 2 ≤ k + 2.
        for depth in 0..=k {
            for s in 0..=depth + 1 {
                let t = depth + 2 - s;
                let cam: Vec<u32> = (0..t).map(|i| vertex_slot(0, i, k)).collect();
                let light: Vec<u32> = (0..s).map(|i| vertex_slot(1, i, k)).collect();
                assert!(cam.iter().chain(&light).all(|&x| x < vertex_slots(k)));
                assert!(cam.iter().all(|c| !light.contains(c)));
            }
        }
    }
}

#[test]
fn density_conversion_uses_the_cosine_only_on_surfaces() {
    let from = Vec3::ZERO;
    let to = Vec3::new(0.0, 0.0, 2.0);
    let n = Vec3::new(0.0, 0.6, -0.8);
    assert!((convert_density(1.0, from, to, n, true) - 0.8 / 4.0).abs() < 1e-6);
    assert!((convert_density(1.0, from, to, n, false) - 0.25).abs() < 1e-6);
    assert_eq!(convert_density(1.0, from, from, n, true), 0.0);
}
