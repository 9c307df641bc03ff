//! Sizes read from the input are checked before anything is allocated: a box's division
//! counts, a mesh deck's `GENERATE` ranges and counts. Each case once panicked ("capacity
//! overflow"), aborted on allocation or wrapped around; now each is an error naming the file,
//! the key or line, and what is wrong.

mod common;
use common::*;
use impact::scene::Scene;
use std::path::{Path, PathBuf};

/// The two bars with body A's divisions replaced; the error of parsing it.
fn divisions_error(divisions: &str) -> String {
    let text = edit(
        &scene_text("two_bars.toml"),
        "divisions = [10, 1, 1] }\nvelocity",
        &format!("divisions = {divisions} }}\nvelocity"),
    );
    let e = Scene::parse(&text, Path::new("bad.toml")).expect_err("must be refused");
    e.to_string()
}

fn expect(msg: &str, parts: &[&str]) {
    assert!(msg.starts_with("bad.toml: "), "names the file: {msg}");
    assert!(
        msg.contains("key `body[0].box.divisions (body `A`)`"),
        "names the key: {msg}"
    );
    for p in parts {
        assert!(msg.contains(p), "{msg:?} should contain {p:?}");
    }
}

#[test]
fn a_million_cubed_divisions_is_refused_not_a_capacity_overflow() {
    let msg = divisions_error("[1000000, 1000000, 1000000]");
    expect(
        &msg,
        &[
            "[1000000, 1000000, 1000000] makes 1000000000000000000 cells and 1000003000003000001 nodes",
            "a body holds at most 4294967295 nodes",
        ],
    );
}

#[test]
fn divisions_past_i32_are_refused_not_an_allocation_abort() {
    let msg = divisions_error("[2147483648, 1, 1]");
    expect(
        &msg,
        &[
            "makes 2147483648 cells and 8589934596 nodes",
            "at most 4294967295 nodes",
        ],
    );
}

#[test]
fn divisions_whose_product_overflows_are_refused_not_wrapped() {
    let msg = divisions_error("[1, 1000000, 9223372036854775807]");
    expect(
        &msg,
        &[
            "makes about 9.223e24 cells and about 1.845e25 nodes",
            "at most 4294967295 nodes",
        ],
    );
}

#[test]
fn a_box_of_exactly_u32_max_nodes_is_accepted_and_one_more_division_is_not() {
    // 255 * 257 * 65537 = 2^32 - 1 nodes; the scene is only checked, not meshed
    let text = edit(
        &scene_text("two_bars.toml"),
        "divisions = [10, 1, 1] }\nvelocity",
        "divisions = [254, 256, 65536] }\nvelocity",
    );
    Scene::parse(&text, Path::new("ok.toml")).expect("u32::MAX nodes are allowed");
    let msg = divisions_error("[254, 256, 65537]");
    expect(&msg, &["4295032830 nodes", "at most 4294967295 nodes"]);
}

/// A copy of `block_hex_drop.toml` and of its deck with `from` replaced by `to`, in a fresh
/// folder; returns the scene's path and the deck's.
fn hex_drop_with_deck(tag: &str, from: &str, to: &str) -> (PathBuf, PathBuf) {
    let dir = out_dir(tag);
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    let deck = std::fs::read_to_string(repo().join("scenes/meshes/block_hex.inp")).unwrap();
    let deck_path = dir.join("meshes/block_hex.inp");
    std::fs::write(&deck_path, edit(&deck, from, to)).unwrap();
    let scene_path = dir.join("block_hex_drop.toml");
    std::fs::write(&scene_path, scene_text("block_hex_drop.toml")).unwrap();
    (scene_path, deck_path)
}

#[test]
fn a_generate_to_i64_max_in_a_scenes_deck_names_the_deck_and_line() {
    let (scene, deck) = hex_drop_with_deck(
        "guard_generate_i64",
        "*ELSET, ELSET=BOTTOM_LAYER, GENERATE\n1, 64, 1",
        "*ELSET, ELSET=BOTTOM_LAYER, GENERATE\n1, 9223372036854775807, 1",
    );
    let msg = Scene::load(&scene)
        .expect_err("must be refused")
        .to_string();
    assert!(
        msg.starts_with(&format!("{}:1760: ", deck.display())),
        "names the deck and line: {msg}"
    );
    assert!(
        msg.contains("makes 9223372036854775807 element numbers"),
        "{msg}"
    );
}

#[test]
fn a_generate_of_a_billion_in_a_scenes_deck_names_the_deck_and_line() {
    let (scene, deck) = hex_drop_with_deck(
        "guard_generate_billion",
        "*ELSET, ELSET=TOP_LAYER, GENERATE\n449, 512, 1",
        "*ELSET, ELSET=TOP_LAYER, GENERATE\n1, 1000000000, 1",
    );
    let msg = Scene::load(&scene)
        .expect_err("must be refused")
        .to_string();
    assert!(
        msg.starts_with(&format!("{}:1762: ", deck.display())),
        "names the deck and line: {msg}"
    );
    assert!(
        msg.contains(
            "makes 1000000000 element numbers, but the file defines at most 1024 elements"
        ),
        "{msg}"
    );
}
