//! Frames that must not change: the SHA-256 of every file of a fixed set of renders, recorded
//! before the restructure of issue 25 ("one direction through the renderer"). A change that
//! moves code around must leave every frame, AOV and count bit for bit as it was; a change
//! that means to alter the pixels updates the table below on purpose (the failure prints the
//! whole new table). Updated once on purpose since: when every transcendental function on the
//! output path moved from the host's C library to the pure-Rust `libm` (issue 20, item 10),
//! which changed last bits (the bunny's frame 0 at 320×240: 306 of 7.77 M queries flipped).
//! Since then these hashes hold on any host whatever its C library. Updated on purpose again
//! for issue 22: the EXR's channels renamed (`shadow.rays`, …) with depth, normal and albedo
//! passes and a header (camera matrices, settings, counts), and the PNGs made through a view
//! transform (AgX by default) and tagged sRGB — every EXR and PNG changed, and the validated
//! renders' stats.csv, whose PSNR is now measured on the AgX previews.
//! The EXR hashes changed once more when every EXR gained its alpha channel `A` (issue 22: all
//! ones over these opaque backgrounds; every other channel, the PNGs and the statistics kept
//! their bits).
//! And once more when the header gained the `[lights] scene_lights` setting (issue 24: the
//! file's own lights; its attribute `envshadow/lights.scene_lights`), the rest unchanged.
//! And with glTF materials (issue 24): the bunny's material (metallic 0, roughness 1) has the
//! rough dielectric's specular, so every bunny EXR and PNG and the validated renders'
//! stats.csv changed; the other stats.csv, every lights.json and the shapes' PNGs (Lambertian)
//! kept their bits, and the EXR headers list the `[render] glossy_env` setting. The bunny
//! rendered with `--lambert` has the PNGs, stats.csv and lights.json of `bunny-brute` before
//! materials.

use crate::common;

use std::path::Path;

use sha2::{Digest, Sha256};

/// One render through the binary: a name, the spec (relative to the repository) and its flags.
struct Render {
    name: &'static str,
    spec: &'static str,
    flags: Vec<String>,
}

/// The bunny at a quarter of its size: what every method is checked on.
const BUNNY: &str = "anims/bunny-turntable.toml";
const SMALL: &str = "--width 320 --height 240";

fn render(name: &'static str, spec: &'static str, flags: &str) -> Render {
    Render {
        name,
        spec,
        flags: flags.split_whitespace().map(String::from).collect(),
    }
}

fn renders() -> Vec<Render> {
    let mut v = vec![
        // The default animation's first frames at one sample per pixel, as the README's
        // first command rendered them before samples per pixel; then at four samples, as it
        // renders them now (recorded when samples per pixel came).
        render(
            "shapes-turntable",
            "anims/shapes-turntable.toml",
            "--frames 0..3 --spp 1",
        ),
        render(
            "shapes-turntable-spp4",
            "anims/shapes-turntable.toml",
            "--frames 0..2 --spp 4",
        ),
    ];
    for (name, method) in [
        ("bunny-none", "none"),
        ("bunny-brute", "brute"),
        ("bunny-scan-warp-boundary", "scan-warp-boundary"),
        ("bunny-grid-warp-boundary", "grid-warp-boundary"),
        ("bunny-grid-nowarp-boundary", "grid-nowarp-boundary"),
        ("bunny-grid-warp-uncertainty", "grid-warp-uncertainty"),
        ("bunny-grid-nowarp-uncertainty", "grid-nowarp-uncertainty"),
        // Added after the restructure (its first method beyond the paper's).
        ("bunny-scan-nowarp-uncertainty", "scan-nowarp-uncertainty"),
    ] {
        let flags = format!("{SMALL} --frames 0..2 --method {method}");
        v.push(render(name, BUNNY, &flags));
    }
    for (name, flags) in [
        (
            "bunny-nowarp-all",
            "--frames 0..2 --method grid-nowarp-uncertainty --flood-to all",
        ),
        (
            "bunny-nowarp-contrary",
            "--frames 0..2 --method grid-nowarp-uncertainty --flood-to contrary",
        ),
        (
            "bunny-warp-contrary",
            "--frames 0..2 --method grid-warp-uncertainty --flood-to contrary",
        ),
        (
            "bunny-tuned",
            "--frames 1 --h0 8 --min-voters 2 --lights 100 --tile 24",
        ),
        (
            "bunny-scan-block",
            "--frames 1 --method scan-warp-boundary --scan-block 32 --tile 48",
        ),
        ("bunny-validate", "--frames 0..2 --validate"),
        (
            "bunny-validate-warp",
            "--frames 1 --validate --method grid-warp-boundary",
        ),
        (
            "bunny-validate-scan",
            "--frames 1 --validate --method scan-warp-boundary",
        ),
        // Orbit: reprojection. Frames 2..6 start mid-chain, so frames 0 and 1 warm it up.
        (
            "bunny-temporal-orbit",
            "--frames 2..6 --temporal --keyframe 4 --validate",
        ),
        (
            "bunny-temporal-warp",
            "--frames 0..3 --temporal --method grid-warp-uncertainty",
        ),
    ] {
        v.push(render(name, BUNNY, &format!("{SMALL} {flags}")));
    }
    // Lambertian materials keep the bits they had before glTF materials: the bunny with
    // --lambert against bunny-brute's hashes as recorded before materials (its materials,
    // metallic 0 and roughness 1, have had specular since).
    v.push(render(
        "bunny-brute-lambert",
        BUNNY,
        &format!("{SMALL} --frames 0..2 --method brute --lambert"),
    ));
    // Spin: votes pulled through the turn, light-space edges.
    v.push(render(
        "bunny-temporal-spin",
        "anims/bunny-spin.toml",
        &format!("{SMALL} --frames 0..4 --temporal --validate"),
    ));
    v
}

/// The recorded hashes: one line per file, `render file sha256`. `stats.csv` is hashed
/// without its `thread_seconds` column, which is a timing, and without the `spp` column
/// added after most were recorded (checked to be the render's own).
const EXPECTED: &str = "\
shapes-turntable frame_0000.exr ba19cdad754a4086b0621c9996d05ff80b875ad499de25d5fd9b1b6e6794eb86
shapes-turntable frame_0000.png 1f10c919481f258193e9f66c95813f9e414a3554cd1e08934d1a9149a4c555b3
shapes-turntable frame_0001.exr 50ee63bf0bccc57643ee240d8e54faab5d7b9d12cc7cbc60373c2154d26e0aa3
shapes-turntable frame_0001.png 029725d6de9a4d5c30d1574db4af180f6db068763742e58f027d3e086f5266b2
shapes-turntable frame_0002.exr 861f77573e2f0c1fe4676266df94fce325b6cd59cae2a41b7a87c0a2cbd6b4ce
shapes-turntable frame_0002.png e962bf93cbfc39be000d61098bbe8e5c4f53131109af13dbea4dc4bac063cb89
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 1a42a982584cfa0f2b48a19bbcc5b168b1cb92d227d6cfc604770d3905e54712
shapes-turntable-spp4 frame_0000.exr 59d0cb01e2f7d4a43fb0ef185dc60818d1ca7aec5c7b64e87d2effb902b36733
shapes-turntable-spp4 frame_0000.png 3001ef5c77757f4ee1e684106fcbfb1774ca443fdc026407d628de97eae7b64e
shapes-turntable-spp4 frame_0001.exr 54951f7d907c97613d1c74ab750eef07a994ddf054c99426e9ae556df0eae795
shapes-turntable-spp4 frame_0001.png 9c2c4784bd5b40a9cab6c92841a240dfdf99677ef48ab6d15138157ffe794b85
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv 3a33a30f809fcdf2742f15c108a8df5cc41aa4f9d1685aac75ebf292b030921a
bunny-none frame_0000.exr da07a77c14ca663e596546383c5c0f772e390e535df95221bee090caca3691f3
bunny-none frame_0000.png 643f65f294962e1da64dc18ae6de02140f59af3a66cc4f483355383ef3e36e1d
bunny-none frame_0001.exr 8f12ef298694c72f28710228ce9438459aa0f78b5ea9102941e696e976168c49
bunny-none frame_0001.png b1cb238899da32f68328df4589e3707bd435037e841cdc3bd92fbbcdeef2fc7e
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv f81d6fe21e7305425deef527fa8b936ee80aa86cbb74e321678e5bc73fda57e5
bunny-brute frame_0000.exr ee4b482279e5a0b5945dbd4f36707e3e3aae92316390a64846f9bae17b5bce23
bunny-brute frame_0000.png a40349e2f26e212a5c1a0769171627c495be9533f8e5e43bda63b5d1626e8db4
bunny-brute frame_0001.exr 750c885ee7f8d66a6ef54a4a775bbc125d44642feeb4c6e4af328346f76f685d
bunny-brute frame_0001.png 43b35e9ff06ca0dd60c7a2a2bf07cdb1d97e8e00f545847a8b5dd15a25e0cd76
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv ecbe98428374ccf54efba77e17cae9f777d3bd21f98341a50f148580a3e62e5a
bunny-scan-warp-boundary frame_0000.exr 87171fba2ba18c229eb753b6c73c8c7c07aad54f74f17201b771832279f8e79f
bunny-scan-warp-boundary frame_0000.png b5875f92ae4375335ab2b594a598778ca39a23402cf8f90f6f4aae91f7dd93be
bunny-scan-warp-boundary frame_0001.exr 2e0213fa6b565ecf9cd4edaec7230d3a471b4951d2fd6bdce9480f658586b5f0
bunny-scan-warp-boundary frame_0001.png 0f77d5e210565479f10987d1ffdd530fd55096daab929fa02309457c045c87e0
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 9a91c445e193e9da2b5567b68a3f396318f29c6f9777ce0c63316b21c9182959
bunny-grid-warp-boundary frame_0000.exr be839ee6fec56e647fe759afb9c39f2ccbed4b47459b1fc5d00110d5cca26419
bunny-grid-warp-boundary frame_0000.png 1577c5c33e04e5bc12d95de7b48593bf15ce7bacd2e82d79fed46f4dcb58dbcb
bunny-grid-warp-boundary frame_0001.exr 6e6d9613c61147995b695b2f796e45bdf9a943167b1a73e2fefefd4453d5e2de
bunny-grid-warp-boundary frame_0001.png 257ca4da7846b2d18f95ea882803bb81075a81a189364d83b1ae105d9a3c7d5c
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv aa2bf7c47bf449e1328eede03814407a420a85cb7407600377ea6c32a69c3b91
bunny-grid-nowarp-boundary frame_0000.exr ef9fc9764bbfb325ec213fd105c1090df69ce5b6174e890f0fe5b70d08011b9f
bunny-grid-nowarp-boundary frame_0000.png a5e790ebc14ba6df03278b88f589a0aa81ca7e431fd02f48eba8335d84d2c598
bunny-grid-nowarp-boundary frame_0001.exr 4243b4fca6671c0eb6e5d331f17a915f51b3772e2c55064ea4804767077dbfbd
bunny-grid-nowarp-boundary frame_0001.png bcbc04c59ae34e2918111818eb66cbc4751b331df498309024284697c2699a29
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 4e2c57cea6dc9b82fbb3c0f0fb89d68763d418cc91b07c6b59541ad43e1ffa25
bunny-grid-warp-uncertainty frame_0000.exr 3389ff96329eae9b64b30142fec3ad192df645d61122393f0de14120f005bdfb
bunny-grid-warp-uncertainty frame_0000.png 29c1a1f2a3e39cae831bc57f0c6521f95716aa98a66e6b2cfb38dddc2ca9d2f8
bunny-grid-warp-uncertainty frame_0001.exr 3033f51207209cb92f4da44d6853aa70febec37e379fc39b588267a3c961de5f
bunny-grid-warp-uncertainty frame_0001.png e01a66f923224ad5ee0bac53a7ad456adf98a53ea1be0483a0ed7ecd8b891265
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv da6051bd0dfb48e496c0d8d82a01da4dde690dd40f43bb428b9cc1eced689e31
bunny-grid-nowarp-uncertainty frame_0000.exr 3405934cb6d0e5a08ee9b50f8928461909c2091654a2d333581ff2bded1c51ff
bunny-grid-nowarp-uncertainty frame_0000.png e8a3bc559dd272aeccb7fe5fc01704dfef00be933d92056ddbeae14998a2b790
bunny-grid-nowarp-uncertainty frame_0001.exr bce4724262a36e04db19b7bfb0b88d6c271cf12a28ddc200aa6b43e304042930
bunny-grid-nowarp-uncertainty frame_0001.png 8dbd3cb660ad814f8c3d7ad4d97eecbe1c30976685c5fef45c4b38253a5bb52e
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv fd8c465b9216f174c843d130d527009f8642ff070b3b9864d49de208a77b9f3c
bunny-scan-nowarp-uncertainty frame_0000.exr 3c28a1cd2620472386c648f116d457dd6ed39e016db2876d97530bd8d90a9511
bunny-scan-nowarp-uncertainty frame_0000.png 401fc6c96ce33cf9163a776e9ad7d8cfc7edf9c56046f9e44afe0d00ac083711
bunny-scan-nowarp-uncertainty frame_0001.exr be4005b99475e1c5a9d1b3fb6e512bdde3a1bf3c6ecb79104ede26a30dd1bf03
bunny-scan-nowarp-uncertainty frame_0001.png d65e4a7b22c6c2e7142a85d624e85aa1eead4f464862c87e2383ff70acbebdf0
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv 20cc516a50e12509ab9fbc198d16f8a7e5ed37e5e2e529a2f4705cace360a6ec
bunny-nowarp-all frame_0000.exr 1db2f621ed2fb8c92f21bcc94e06af73411d68094cf360100c7e12a45adf053e
bunny-nowarp-all frame_0000.png 9503475e01639383cc4853e891d63968c06a1ab5b1ab3ae3cec393c1d90062fb
bunny-nowarp-all frame_0001.exr 16fbb897d02de4acadcd284307b2563ef8e59d2b306be896e5808af81ea805ee
bunny-nowarp-all frame_0001.png 30063c666abfc65e9e3f381892067013a6272bd0c7b016e7fff27cd1b223841f
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv 6a2cbcb96d5c7adb62a2878e475572745229f2319865b306db4d7373221342ae
bunny-nowarp-contrary frame_0000.exr 1285fd2897d8e8b095371e17ac547ac84d733bce2b704b0085a8d91e56be0fe2
bunny-nowarp-contrary frame_0000.png e5477e2510a1b2adeded69402be8c33e6011226e1cc74d5a196cd6327b0e0f2b
bunny-nowarp-contrary frame_0001.exr b8d0e218dec928043707cfdc55bbb97cf86e0f625d8726f6d36d824fdbd0e928
bunny-nowarp-contrary frame_0001.png e9a59bcd02c422cc29e7aead38417edf9daf4d01ab985c7d795ca5e9f306d98b
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv e4d99b9574d7ff1331da9ebb04e44af4f719af81194c9933d2d7199bbc6af237
bunny-warp-contrary frame_0000.exr f9b704fcd2197b80e9730fe70e962223205a493ebd1a45357941cd4ea4323081
bunny-warp-contrary frame_0000.png 9e79ef7b4c761c5fb698b619c9e2f439b10928f41badc8d362440961388d5266
bunny-warp-contrary frame_0001.exr 058a6e87c0c46ab8ec51c01051e0a65a4b9cae6c0d0f1c6c16f7602de37730ee
bunny-warp-contrary frame_0001.png 574e44f3ad7b4feda78c87f55ec7624fbacacea1ce91417556f3bc2f191d2a02
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv 18492050db107104367d377cf5077dc390752a9db8982d6fcafade61bf5bebd7
bunny-tuned frame_0001.exr a5a9193f9ec6465a93d6fe6660d4edf63e2a3ac382dbffe376c7ef9618f2e620
bunny-tuned frame_0001.png 5152dae6dc229f56b560ec5da0c782c7aec1f48578630f6fc0a02d1c9f4c8575
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv e8701d2de96517a69e08d5360f53e2f277b88d50524aa61a061c5d1c7719c9c0
bunny-scan-block frame_0001.exr acb9b452802b84d415196c026bd0e7990b8e822f437c6c266caf71025706b333
bunny-scan-block frame_0001.png fc31d8715dd95eb33d953ece63fdaa73cb2075d32fe6ffebc218327914bfa0ba
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv f98ef6c8eda859fde763d085d27aae55e6456cd89010e8a05ed9c27adc32a64b
bunny-validate frame_0000.exr 3285ea29035ab5da1e9e1ffb46709624a55b7cdcdc37b1f1b01659d667195fc2
bunny-validate frame_0000.png e8a3bc559dd272aeccb7fe5fc01704dfef00be933d92056ddbeae14998a2b790
bunny-validate frame_0001.exr 1c89cb0be2445a1094c1032a0b7d7d58cc4055e4c4f77cef688a237ac90d9076
bunny-validate frame_0001.png 8dbd3cb660ad814f8c3d7ad4d97eecbe1c30976685c5fef45c4b38253a5bb52e
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv 9d7194a59aa7b6ae0169892a89088b5cd2f550a7eb031a64e8f0ebb6367a9be1
bunny-validate-warp frame_0001.exr fef99e39ddc887fba0edce281c59bbae5764ea35b11f84f143c59665b02a3e5d
bunny-validate-warp frame_0001.png 257ca4da7846b2d18f95ea882803bb81075a81a189364d83b1ae105d9a3c7d5c
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 467cf7670e72521c5b48e76ff3aefb58b83e085375382580428226363cccc99f
bunny-validate-scan frame_0001.exr df0a7ddb5717f387530a3946d3d8165e3fdf107fca1d7d35681f8b76a89728e6
bunny-validate-scan frame_0001.png 0f77d5e210565479f10987d1ffdd530fd55096daab929fa02309457c045c87e0
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv 0a91cb5193527f9ba17ec361bb93a13c3e4012e75d0a617b85b7692e20d56526
bunny-temporal-orbit frame_0002.exr a836ca186ad16c1a28a4a34fe5ed383d2717471ced2b1e8027d2e4ee21f4e4e7
bunny-temporal-orbit frame_0002.png 27c68b99e6ec42402c6ba46b7fa144a4e1794070d88757765c31eeff01b46c93
bunny-temporal-orbit frame_0003.exr 1d8b1e2ee4b8e474c5fc310373c4fc12776809f5718b616a0429b5278556a739
bunny-temporal-orbit frame_0003.png fc75d19c092093eb086721bacda81555be9f6353e122de4688cf54e66fe09eef
bunny-temporal-orbit frame_0004.exr 8db6839266ac049ebbe58ff9496a6b08079a3a67b214ecf3afd1afe31c3475b8
bunny-temporal-orbit frame_0004.png df687467ca6748f6b41337f1048960148a86447102d9538b8d8cf4f919c3adfb
bunny-temporal-orbit frame_0005.exr 41c34f7621768acfb73c68d4a95bf3f573b265b998079fc57463590abb2d622d
bunny-temporal-orbit frame_0005.png 6a713ad7f2cfb7f1d181dd12f9a9cbe2acca9d0bb7cbaa939f3883f3d04328b0
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv f81c3fff9d387de02ddcdb21734ceb484cee9bd5220b31ad3862054aff76b8d3
bunny-temporal-warp frame_0000.exr b0c813d440813f78b91c0960883fb3117a94c8445d7a72b81f9fb461db43f78c
bunny-temporal-warp frame_0000.png 29c1a1f2a3e39cae831bc57f0c6521f95716aa98a66e6b2cfb38dddc2ca9d2f8
bunny-temporal-warp frame_0001.exr 891a65752397d95a6395e0a54f99eb297c35cc076cc8b01a0373931774519fbb
bunny-temporal-warp frame_0001.png f5f6bb0cc1d60ebf8cc4386e4ae3cfd40f80bfdb3cea7c0fc8547bb3db7ffcfd
bunny-temporal-warp frame_0002.exr 82a733d8c706e8b75b64b85d2469ec8c8ec4827a4fa1407f475b3b6c1687a098
bunny-temporal-warp frame_0002.png 2117fdb068bf30bddd566936b55c2d5b1d7575ceb080cf852ba32034c394ad34
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 3e7d7ced40a8121859edbf11470a184f9450cee9c22794424b93ff8aba9f00ae
bunny-brute-lambert frame_0000.exr 1890864a68b439aa72f6565b9ec76cc0d435e88221f736ffc6285f12dac4b936
bunny-brute-lambert frame_0000.png ee648a99eb3f1b3129bab45f64dcfa09c3de1cb9711595a4ec51b1462c72f6ca
bunny-brute-lambert frame_0001.exr d1b64e4f1b6d58c8ce03ab3ec5da8bee0cf26cd29cfd3cb6470e159900f1c1fb
bunny-brute-lambert frame_0001.png d81e4b8d6a073bf3881c7a34f7d26cb29a3274c97c196b6d9b5016d7335b8f00
bunny-brute-lambert lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute-lambert stats.csv ecbe98428374ccf54efba77e17cae9f777d3bd21f98341a50f148580a3e62e5a
bunny-temporal-spin frame_0000.exr 86ca9289c278031174b294996f8eb99acb3a52e3fe2be42e3e18c2c06ee85f68
bunny-temporal-spin frame_0000.png f96b6ef2a1fb6f296f32a53f1c4513fcf72631b04a5d1812bbd2ae63b9853dad
bunny-temporal-spin frame_0001.exr 5d57a40d77f80d0421b39ee30aa2b9252d8ac1cafca3e17f9b9fec575bfb1dc3
bunny-temporal-spin frame_0001.png 8c42427562ff654d0ab1c1a81b3af58cca26c8fad799b5174aaf41b766e5b66c
bunny-temporal-spin frame_0002.exr 6a8429dc9db1a93cde8d45b2b3411ed6bee49fb9b005dff4dcb57e4d3e2fba0b
bunny-temporal-spin frame_0002.png 5184c207f2500d2dff6264ee1109c5b3e59df1c961d754dca17245827bea424e
bunny-temporal-spin frame_0003.exr 7b3516ef94272ce8575f8d9b775d5bd28374cedbd4a6b588e190905c9007236c
bunny-temporal-spin frame_0003.png 710e2ef2cbe90023128183d69bb07e2bfe4bb3eacc4cb75aa41f61c699999595
bunny-temporal-spin lights.json 103f720aa426b7ad9ed05f0b47b0a7d9096a5429b996d950aa4e62c981aa7cd5
bunny-temporal-spin stats.csv 7cf2cf8655c848e5ef0bd3c1211d18682e5aa8df9752ab4f9d0a9a88a7d0861c
";

fn sha(bytes: &[u8]) -> String {
    format!("{:x}", Sha256::digest(bytes))
}

/// `stats.csv` with the `thread_seconds` column emptied and the last column, `spp`, removed once
/// checked to be `spp` everywhere.
fn stats_without_seconds(text: &str, spp: &str) -> String {
    let mut lines = text.lines();
    let mut header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "thread_seconds")
        .expect("stats.csv has a thread_seconds column");
    assert_eq!(
        header.pop(),
        Some("spp"),
        "stats.csv ends with the spp column"
    );
    let mut out = format!("{}\n", header.join(","));
    for line in lines {
        let mut f: Vec<&str> = line.split(',').collect();
        f[col] = "";
        assert_eq!(f.pop(), Some(spp), "a golden render at {spp} spp: {line}");
        out.push_str(&f.join(","));
        out.push('\n');
    }
    out
}

/// The output files of one render folder (frames, lights, stats), hashed, in name order.
/// `lights.json` names the map it came from: the assets folder is hashed as `ASSETS`, so the
/// hashes do not depend on where the repository and its assets are. The bookkeeping for
/// `--resume` (`settings.txt`, `records/`) is not output.
fn hashes(dir: &Path, assets: &str, spp: &str) -> Vec<(String, String)> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "settings.txt" && dir.join(n).is_file())
        .collect();
    names.sort();
    names
        .into_iter()
        .map(|n| {
            let bytes = std::fs::read(dir.join(&n)).unwrap();
            let h = if n == "stats.csv" {
                sha(stats_without_seconds(&String::from_utf8(bytes).unwrap(), spp).as_bytes())
            } else if n == "lights.json" {
                sha(String::from_utf8(bytes)
                    .unwrap()
                    .replace(assets, "ASSETS/")
                    .as_bytes())
            } else {
                sha(&bytes)
            };
            (n, h)
        })
        .collect()
}

#[test]
fn every_recorded_frame_keeps_its_bits() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    let assets = common::assets_dir();
    let mut got: Vec<(String, String, String)> = Vec::new();
    for r in renders() {
        let out = tmp.path().join(r.name);
        // The specs name their files under ../assets; point them at the test assets.
        let text = std::fs::read_to_string(root.join(r.spec)).unwrap();
        let spec = tmp.path().join(format!("{}.toml", r.name));
        let dir = format!("{}/", assets.display());
        std::fs::write(&spec, text.replace("../assets/", &dir)).unwrap();
        let o = common::bin()
            .args(["render", "-q", "--no-report"])
            .arg(&spec)
            .args(&r.flags)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{}: {}",
            r.name,
            String::from_utf8_lossy(&o.stderr)
        );
        let spp = r
            .flags
            .iter()
            .position(|f| f == "--spp")
            .map_or("1", |k| r.flags[k + 1].as_str());
        for (file, h) in hashes(&out, &dir, spp) {
            got.push((r.name.to_string(), file, h));
        }
    }
    let table: String = got
        .iter()
        .map(|(r, f, h)| format!("{r} {f} {h}\n"))
        .collect();
    let expected: Vec<(String, String, String)> = EXPECTED
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(' ').collect();
            (f[0].to_string(), f[1].to_string(), f[2].to_string())
        })
        .collect();
    let changed: Vec<String> = got
        .iter()
        .filter(|g| !expected.contains(g))
        .map(|(r, f, _)| format!("{r}/{f}"))
        .chain(
            expected
                .iter()
                .filter(|e| !got.iter().any(|g| g.0 == e.0 && g.1 == e.1))
                .map(|(r, f, _)| format!("{r}/{f} (missing)")),
        )
        .collect();
    assert!(
        changed.is_empty(),
        "{} file(s) changed: {}\nthe new table:\n{table}",
        changed.len(),
        changed.join(", ")
    );
}
