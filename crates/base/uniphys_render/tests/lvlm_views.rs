//! The LVLM views: colours where they should be, determinism, translucency.

use uniphys_geometry::{DVec3, TriMesh};
use uniphys_render::{
    AXIS_COLOURS, PIVOT_COLOURS, PartScene, RgbaImage, ViewOptions, axis_candidate_views,
    camera_from_direction, encode_png, part_composite, pivot_candidate_views,
};

const RED_PART: [u8; 4] = [220, 40, 40, 255];
const GREEN_PART: [u8; 4] = [40, 170, 60, 255];

/// A red-dominated pixel: the red part, possibly seen through translucent grey.
fn reddish(p: [u8; 4]) -> bool {
    i32::from(p[0]) > i32::from(p[1]) + 30 && i32::from(p[0]) > i32::from(p[2]) + 30
}

fn count_in(img: &RgbaImage, x0: u32, x1: u32, pred: impl Fn([u8; 4]) -> bool) -> usize {
    let mut n = 0;
    for y in 0..img.height_px {
        for x in x0..x1.min(img.width_px) {
            if pred(img.get(x, y)) {
                n += 1;
            }
        }
    }
    n
}

/// A cabinet-like object: a grey body and a red door in front of it.
fn cabinet() -> Vec<TriMesh> {
    vec![
        TriMesh::cuboid(DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.6, 0.4, 0.8)),
        TriMesh::cuboid(DVec3::new(0.05, -0.03, 0.05), DVec3::new(0.55, 0.0, 0.75)),
    ]
}

#[test]
fn the_part_composite_shows_the_target_in_its_colour_in_all_three_panels() {
    let meshes = cabinet();
    let colours = [GREEN_PART, RED_PART];
    let scene = PartScene {
        part_meshes: &meshes,
        part_rgba: &colours,
    };
    let options = ViewOptions { panel_px: 96 };
    let img = part_composite(&scene, 1, &options);
    let panel_w = 96 + 8;
    assert_eq!(img.width_px, 3 * 96 + 2 * 8);
    assert!(img.height_px > 96);
    assert!(img.pixels.iter().all(|p| p[3] == 255), "opaque");
    for panel in 0..3 {
        let x0 = panel * panel_w;
        let red = count_in(&img, x0, x0 + 96, reddish);
        assert!(red > 150, "panel {panel}: {red} red pixels");
    }
    // View 1 looks from the back (+y): the door is behind the body, seen through it.
    // The alone panel is filled by the part: more red there than in the context panels.
    let alone = count_in(&img, 2 * panel_w, 2 * panel_w + 96, reddish);
    let view0 = count_in(&img, 0, 96, reddish);
    assert!(alone > view0, "alone {alone} vs view 0 {view0}");
    // The body is green in its own composite; in the door's composite it is grey.
    let greenish = |p: [u8; 4]| i32::from(p[1]) > i32::from(p[0]) + 30;
    assert_eq!(count_in(&img, 0, img.width_px, greenish), 0);
    let body = part_composite(&scene, 0, &options);
    assert!(count_in(&body, 0, 96, greenish) > 150);
    assert_eq!(part_composite(&scene, 1, &options), img, "deterministic");
}

#[test]
fn an_occluded_part_shows_through_the_translucent_box_around_it() {
    let meshes = vec![
        TriMesh::cuboid(DVec3::splat(-1.0), DVec3::splat(1.0)),
        TriMesh::cuboid(DVec3::splat(-0.3), DVec3::splat(0.3)),
    ];
    let colours = [GREEN_PART, RED_PART];
    let scene = PartScene {
        part_meshes: &meshes,
        part_rgba: &colours,
    };
    let img = part_composite(&scene, 1, &ViewOptions { panel_px: 80 });
    for panel in 0..2 {
        let x0 = panel * (80 + 8);
        let red = count_in(&img, x0, x0 + 80, reddish);
        assert!(red > 100, "context panel {panel}: {red} red pixels");
    }
    // The rest is grey: no green anywhere in the target's composite.
    assert_eq!(
        count_in(&img, 0, img.width_px, |p| i32::from(p[1])
            > i32::from(p[0]) + 30),
        0
    );
}

#[test]
fn every_axis_colour_appears_and_the_frame_axes_are_on_the_right_panel() {
    let meshes = cabinet();
    let colours = [GREEN_PART, RED_PART];
    let scene = PartScene {
        part_meshes: &meshes,
        part_rgba: &colours,
    };
    let n = DVec3::new(0.0, -1.0, 0.0);
    let mut axes = [DVec3::ZERO; 10];
    axes[0] = n;
    for (m, axis) in axes[1..7].iter_mut().enumerate() {
        let angle = m as f64 * std::f64::consts::PI / 6.0;
        *axis = DVec3::new(angle.cos(), 0.0, angle.sin()) * 0.7; // not unit, like the reference
    }
    axes[7] = DVec3::X;
    axes[8] = DVec3::Y;
    axes[9] = DVec3::Z;
    let options = ViewOptions { panel_px: 120 };
    let origin = DVec3::new(0.3, -0.03, 0.4);
    let views = axis_candidate_views(&scene, 1, &axes, origin, &options);
    for img in &views {
        let half = 120 + 8;
        assert!(img.width_px >= 2 * 120 + 8);
        for (i, (name, rgba)) in AXIS_COLOURS.iter().enumerate() {
            let (left, right) = (
                img_count(img, 0, 120, *rgba),
                img_count(img, half, half + 120, *rgba),
            );
            // Legends sit under the renders: count only the render area for placement.
            let (left_render, right_render) = (
                render_count(img, 0, *rgba, options.panel_px),
                render_count(img, half, *rgba, options.panel_px),
            );
            if i < 7 {
                assert!(
                    left_render > 10,
                    "{name}: {left_render} px in the contact panel"
                );
                assert!(left > left_render, "{name} in the legend");
            } else {
                assert!(
                    right_render > 10,
                    "{name}: {right_render} px in the frame panel"
                );
                assert!(right > right_render, "{name} in the legend");
            }
        }
    }
    assert_ne!(views[0], views[1]);
    let again = axis_candidate_views(&scene, 1, &axes, origin, &options);
    assert_eq!(
        encode_png(&again[0]).expect("png"),
        encode_png(&views[0]).expect("png")
    );
}

fn img_count(img: &RgbaImage, x0: u32, x1: u32, rgba: [u8; 4]) -> usize {
    count_in(img, x0, x1, |p| p == rgba)
}

/// Pixels of exactly `rgba` in the square render under the title of the panel starting at `x0`.
fn render_count(img: &RgbaImage, x0: u32, rgba: [u8; 4], panel_px: u32) -> usize {
    let top = title_height(img, x0);
    let mut n = 0;
    for y in top..top + panel_px {
        for x in x0..x0 + panel_px {
            n += usize::from(img.get(x, y) == rgba);
        }
    }
    n
}

/// The first row of the panel's red frame: where the render starts.
fn title_height(img: &RgbaImage, x0: u32) -> u32 {
    (0..img.height_px)
        .find(|&y| img.get(x0, y) == [220, 30, 30, 255])
        .expect("framed panel")
}

#[test]
fn each_pivot_colour_is_drawn_around_its_projected_position() {
    let meshes = cabinet();
    let colours = [GREEN_PART, RED_PART];
    let scene = PartScene {
        part_meshes: &meshes,
        part_rgba: &colours,
    };
    let pivots = [
        DVec3::new(0.3, -0.015, 0.4),
        DVec3::new(0.05, -0.015, 0.1),
        DVec3::new(0.55, -0.015, 0.1),
        DVec3::new(0.05, -0.015, 0.7),
        DVec3::new(0.55, -0.015, 0.7),
        DVec3::new(0.3, -0.015, 0.05),
    ];
    let options = ViewOptions { panel_px: 160 };
    let views = pivot_candidate_views(&scene, 1, &pivots, &options);
    // The camera frames the part and the pivots, as the view does.
    let mut framed = meshes[1].bounds();
    for p in &pivots {
        framed = framed.grown(*p);
    }
    for (view, img) in views.iter().enumerate() {
        let top = title_height(img, 0);
        let dir = uniphys_render::lvlm_views::VIEW_DIRECTIONS[view];
        let cam = camera_from_direction(&framed, DVec3::from_array(dir), 160, 160);
        for (pivot, (name, rgba)) in pivots.iter().zip(PIVOT_COLOURS) {
            let p = cam.project(*pivot).expect("in view");
            let (cx, cy) = (p.x_px as u32, p.y_px as u32 + top);
            let mut near = 0;
            for y in cy.saturating_sub(3)..=cy + 3 {
                for x in cx.saturating_sub(3)..=cx + 3 {
                    near += usize::from(img.get(x, y) == rgba);
                }
            }
            assert!(
                near >= 25,
                "view {view} {name}: {near} px near ({cx}, {cy})"
            );
        }
    }
    assert_eq!(pivot_candidate_views(&scene, 1, &pivots, &options), views);
}

#[test]
fn degenerate_scenes_give_images_without_panicking() {
    let options = ViewOptions { panel_px: 64 };
    let empty = PartScene {
        part_meshes: &[],
        part_rgba: &[],
    };
    let img = part_composite(&empty, 3, &options);
    assert_eq!(img.width_px, 3 * 64 + 2 * 8);
    let meshes = cabinet();
    // No colours given, a part index past the end, zero and non-finite axes and pivots.
    let scene = PartScene {
        part_meshes: &meshes,
        part_rgba: &[],
    };
    let img = part_composite(&scene, 7, &options);
    assert_eq!(img.width_px, 3 * 64 + 2 * 8);
    let mut axes = [DVec3::ZERO; 10];
    axes[7] = DVec3::new(f64::NAN, 0.0, 1.0);
    axes[8] = DVec3::Y;
    let views = axis_candidate_views(&scene, 0, &axes, DVec3::new(0.3, 0.2, 0.4), &options);
    let green = AXIS_COLOURS[8].1;
    assert!(
        render_count(&views[0], 64 + 8, green, 64) > 5,
        "the one valid axis is drawn"
    );
    assert_eq!(render_count(&views[0], 64 + 8, AXIS_COLOURS[7].1, 64), 0);
    let pivots = [DVec3::splat(f64::INFINITY); 6];
    let views = pivot_candidate_views(&scene, 1, &pivots, &options);
    assert_eq!(views[0].width_px, 64);
    for (_, rgba) in PIVOT_COLOURS {
        assert_eq!(render_count(&views[0], 0, rgba, 64), 0);
    }
}
