//! Built-in scenes: TOML files under `scenes/` compiled into the binary.

pub struct BuiltinScene {
    pub name: &'static str,
    pub toml: &'static str,
}

pub const BUILTIN_SCENES: &[BuiltinScene] = &[
    BuiltinScene { name: "ocean", toml: include_str!("../../../../scenes/ocean.toml") },
    BuiltinScene { name: "sunset", toml: include_str!("../../../../scenes/sunset.toml") },
    BuiltinScene { name: "storm", toml: include_str!("../../../../scenes/storm.toml") },
    BuiltinScene { name: "calm", toml: include_str!("../../../../scenes/calm.toml") },
    BuiltinScene { name: "lake", toml: include_str!("../../../../scenes/lake.toml") },
    BuiltinScene { name: "pool", toml: include_str!("../../../../scenes/pool.toml") },
    BuiltinScene { name: "harbor", toml: include_str!("../../../../scenes/harbor.toml") },
    BuiltinScene { name: "coastal", toml: include_str!("../../../../scenes/coastal.toml") },
    BuiltinScene { name: "underwater", toml: include_str!("../../../../scenes/underwater.toml") },
    BuiltinScene { name: "wake", toml: include_str!("../../../../scenes/wake.toml") },
    BuiltinScene { name: "dam_break", toml: include_str!("../../../../scenes/dam_break.toml") },
    BuiltinScene { name: "pour", toml: include_str!("../../../../scenes/pour.toml") },
    BuiltinScene { name: "fountain", toml: include_str!("../../../../scenes/fountain.toml") },
    BuiltinScene {
        name: "water_dragon",
        toml: include_str!("../../../../scenes/water_dragon.toml"),
    },
];
