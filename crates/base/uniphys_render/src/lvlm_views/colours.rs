/// Names and RGBA of the 10 candidate-axis colours, in candidate order: Yellow, Orange, Purple,
/// Cyan, Magenta, Dark Gray, Brown (the 7 contact-derived candidates: normal then 6 in-plane),
/// then Red, Green, Blue for the three frame axes in the order given. Our frame axes are world
/// X, Y, Z, so Red = X, Green = Y, Blue = Z (the reference printed Red = Z); each arrow is
/// labelled and the legend states it. The first seven match the reference's Blender colours.
pub const AXIS_COLOURS: [(&str, [u8; 4]); 10] = [
    ("Yellow", [255, 255, 0, 255]),
    ("Orange", [255, 128, 0, 255]),
    ("Purple", [153, 51, 255, 255]),
    ("Cyan", [0, 255, 255, 255]),
    ("Magenta", [255, 0, 255, 255]),
    ("Dark Gray", [70, 70, 70, 255]),
    ("Brown", [102, 64, 26, 255]),
    ("Red", [255, 0, 0, 255]),
    ("Green", [0, 200, 0, 255]),
    ("Blue", [0, 0, 255, 255]),
];

/// Red, Green, Blue, Yellow, Purple, Brown: the 6 pivot candidates in candidate order (the five
/// k-means centres of the contact points, then their centroid, Brown).
pub const PIVOT_COLOURS: [(&str, [u8; 4]); 6] = [
    ("Red", [255, 0, 0, 255]),
    ("Green", [0, 200, 0, 255]),
    ("Blue", [0, 0, 255, 255]),
    ("Yellow", [255, 255, 0, 255]),
    ("Purple", [153, 51, 255, 255]),
    ("Brown", [102, 64, 26, 255]),
];

/// Names of the frame axes drawn with the last three [`AXIS_COLOURS`].
pub const FRAME_AXIS_NAMES: [&str; 3] = ["X", "Y", "Z"];

/// Panel background.
pub(crate) const WHITE: [u8; 4] = [255, 255, 255, 255];
/// Text and outlines.
pub(crate) const INK: [u8; 4] = [20, 20, 20, 255];
/// Panel frame (the reference framed each panel in red).
pub(crate) const FRAME: [u8; 4] = [220, 30, 30, 255];
/// Base colour of the context parts before shading.
pub(crate) const CONTEXT_GREY: [u8; 3] = [205, 205, 205];
/// Colour of a part without one in the scene.
pub(crate) const DEFAULT_PART: [u8; 4] = [70, 120, 200, 255];
