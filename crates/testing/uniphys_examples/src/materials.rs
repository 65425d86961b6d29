//! The named visual materials of the examples. Names say the material (`<class>_<kind>`) so that
//! a material grounder can read them; colours are plausible linear-RGB base colours.

use uniphys_geometry::SurfaceMaterial;

/// A named material with its linear RGBA base colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct NamedMaterial {
    /// Material name written to the glTF file.
    pub name: &'static str,
    /// Linear RGBA base colour.
    pub rgba: [f32; 4],
}

impl NamedMaterial {
    /// The material as a [`SurfaceMaterial`] without texture.
    pub fn surface(self) -> SurfaceMaterial {
        SurfaceMaterial {
            name: self.name.to_owned(),
            base_color_rgba: self.rgba,
            base_color_texture: None,
        }
    }
}

/// Oak veneer, mid brown.
pub(crate) const WOOD_OAK: NamedMaterial = NamedMaterial {
    name: "wood_oak",
    rgba: [0.48, 0.26, 0.10, 1.0],
};

/// Pine, light yellowish brown.
pub(crate) const WOOD_PINE: NamedMaterial = NamedMaterial {
    name: "wood_pine",
    rgba: [0.70, 0.45, 0.21, 1.0],
};

/// Brushed steel.
pub(crate) const METAL_STEEL: NamedMaterial = NamedMaterial {
    name: "metal_steel",
    rgba: [0.56, 0.57, 0.58, 1.0],
};

/// Anodised aluminium, silver.
pub(crate) const METAL_ALUMINIUM: NamedMaterial = NamedMaterial {
    name: "metal_aluminium",
    rgba: [0.91, 0.92, 0.92, 1.0],
};

/// Dark grey ABS plastic.
pub(crate) const PLASTIC_ABS: NamedMaterial = NamedMaterial {
    name: "plastic_abs",
    rgba: [0.03, 0.03, 0.035, 1.0],
};

/// The black glass cover of a display.
pub(crate) const GLASS_BLACK: NamedMaterial = NamedMaterial {
    name: "glass_black",
    rgba: [0.01, 0.01, 0.012, 1.0],
};

/// Glazed white ceramic.
pub(crate) const CERAMIC_GLAZE: NamedMaterial = NamedMaterial {
    name: "ceramic_glaze",
    rgba: [0.85, 0.84, 0.80, 1.0],
};
