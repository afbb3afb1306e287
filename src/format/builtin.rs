//! The automata shipped in `automata/`, embedded in the library.

/// The automata shipped in `automata/`: `(name, file text)`.
pub const BUILTIN_AUTOMATA: &[(&str, &str)] = &[
    ("cantor", include_str!("../../automata/cantor.toml")),
    ("cantor_dust", include_str!("../../automata/cantor_dust.toml")),
    ("carpet", include_str!("../../automata/carpet.toml")),
    ("corner_cutting", include_str!("../../automata/corner_cutting.toml")),
    ("cube_lace", include_str!("../../automata/cube_lace.toml")),
    ("curve_4_3", include_str!("../../automata/curve_4_3.toml")),
    ("doo_sabin_quad", include_str!("../../automata/doo_sabin_quad.toml")),
    ("doo_sabin_torus", include_str!("../../automata/doo_sabin_torus.toml")),
    ("fern", include_str!("../../automata/fern.toml")),
    ("fern_sierpinski", include_str!("../../automata/fern_sierpinski.toml")),
    ("gasket", include_str!("../../automata/gasket.toml")),
    ("gasket_bezier", include_str!("../../automata/gasket_bezier.toml")),
    ("gasket_lace", include_str!("../../automata/gasket_lace.toml")),
    ("jerusalem", include_str!("../../automata/jerusalem.toml")),
    ("koch", include_str!("../../automata/koch.toml")),
    ("levy", include_str!("../../automata/levy.toml")),
    ("menger", include_str!("../../automata/menger.toml")),
    ("octahedron_lace", include_str!("../../automata/octahedron_lace.toml")),
    ("sierpinski_tetrahedron", include_str!("../../automata/sierpinski_tetrahedron.toml")),
];
