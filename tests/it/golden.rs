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
shapes-turntable frame_0000.exr 0ea6ae02c98f858e82a09e1e148761431d9a0671a4b85dc73ac24ea42aa415f3
shapes-turntable frame_0000.png 1f10c919481f258193e9f66c95813f9e414a3554cd1e08934d1a9149a4c555b3
shapes-turntable frame_0001.exr 4bb702bceb11c1f7e7101dab7829839a11de1ebcaafa0b2e910e3fb1599c89cf
shapes-turntable frame_0001.png 3a804d02fa3693f40a028208156d0d1a76640b191100451a6a1ee1e0d2d75fe7
shapes-turntable frame_0002.exr 198fe0a9b1c972ab4a8ffcf3fab451b6c32de60e6ac746022b4ef8fe9e31178c
shapes-turntable frame_0002.png 946f69e3082377a9708c654831e73d52036d82deef8037100759f8cacb077daa
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 2a17a4a7b486226ca398844916240dcda498665fb5a178ea24bed8717654ff71
shapes-turntable-spp4 frame_0000.exr 3cc37662a1e8e77a51804f5d60ea1d8e86674e76070bc81ae6605cd9906c9b77
shapes-turntable-spp4 frame_0000.png 00b2104d53a832166e4cbffcc270fbeec61435cdeefc571c234194b8cdcf031c
shapes-turntable-spp4 frame_0001.exr 72ea481a98c7e054d9e87c0b9827ccd087ab870bfc08d35168aecd3be681a6c8
shapes-turntable-spp4 frame_0001.png ed96fc8d8e9019f2c2eb9ba52067e44a471e19e750943c04aaf2ce3fc21703d4
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv ac06052c2d6632def8161c66e4893519336835b30478f662db656262346dfa9e
bunny-none frame_0000.exr 80ad07efa8263b8226fa2f177353b6be9579f4b996918dbcd9686999e4eec19f
bunny-none frame_0000.png 643f65f294962e1da64dc18ae6de02140f59af3a66cc4f483355383ef3e36e1d
bunny-none frame_0001.exr dcb728ef83dadfca8238619433f29f44d4fdf602fd4fa092dfcde339c79b8bb8
bunny-none frame_0001.png b1cb238899da32f68328df4589e3707bd435037e841cdc3bd92fbbcdeef2fc7e
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv f81d6fe21e7305425deef527fa8b936ee80aa86cbb74e321678e5bc73fda57e5
bunny-brute frame_0000.exr 6272ec022da9016d681d8ac65af31bb8223a1b2d3ec8cabf10d980e2d1d142a1
bunny-brute frame_0000.png a40349e2f26e212a5c1a0769171627c495be9533f8e5e43bda63b5d1626e8db4
bunny-brute frame_0001.exr 57b154a3375ec1d555b38e44997e247d1963c079ea8c16ded5b27c97796a1686
bunny-brute frame_0001.png 43b35e9ff06ca0dd60c7a2a2bf07cdb1d97e8e00f545847a8b5dd15a25e0cd76
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv ecbe98428374ccf54efba77e17cae9f777d3bd21f98341a50f148580a3e62e5a
bunny-scan-warp-boundary frame_0000.exr 3914af0ffd3752ab25ef6d1c30947df7aac790d91d068ab2a58215239dfbaad9
bunny-scan-warp-boundary frame_0000.png b5875f92ae4375335ab2b594a598778ca39a23402cf8f90f6f4aae91f7dd93be
bunny-scan-warp-boundary frame_0001.exr d03acd0d0a55ef635b57dd5f849da1b690fd28c9000cf7bde8ebc53d92df6def
bunny-scan-warp-boundary frame_0001.png 0f77d5e210565479f10987d1ffdd530fd55096daab929fa02309457c045c87e0
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 9a91c445e193e9da2b5567b68a3f396318f29c6f9777ce0c63316b21c9182959
bunny-grid-warp-boundary frame_0000.exr 4f41c40406719cf545762010a62994031ad536480df9d6e5e6a6339bca90d75b
bunny-grid-warp-boundary frame_0000.png 1577c5c33e04e5bc12d95de7b48593bf15ce7bacd2e82d79fed46f4dcb58dbcb
bunny-grid-warp-boundary frame_0001.exr 8f7479f914ad02f2936eda9e5d9490602f83c4bce81e9613774d574adf94d1bb
bunny-grid-warp-boundary frame_0001.png 257ca4da7846b2d18f95ea882803bb81075a81a189364d83b1ae105d9a3c7d5c
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv aa2bf7c47bf449e1328eede03814407a420a85cb7407600377ea6c32a69c3b91
bunny-grid-nowarp-boundary frame_0000.exr f4eeaa4fa9c3e2d432140405f0a19e15dd4f5ac2f56d04515d63ce792a99f9d1
bunny-grid-nowarp-boundary frame_0000.png a5e790ebc14ba6df03278b88f589a0aa81ca7e431fd02f48eba8335d84d2c598
bunny-grid-nowarp-boundary frame_0001.exr d1e48e6f2b3bf782ef1834dbb13a63fe20a932ba501d750f4b058a01605b8f97
bunny-grid-nowarp-boundary frame_0001.png bcbc04c59ae34e2918111818eb66cbc4751b331df498309024284697c2699a29
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 4e2c57cea6dc9b82fbb3c0f0fb89d68763d418cc91b07c6b59541ad43e1ffa25
bunny-grid-warp-uncertainty frame_0000.exr efdcf818a5c3676a63d7c7cf9808e6cda4f57031a31565a396823e99994ef7b7
bunny-grid-warp-uncertainty frame_0000.png 29c1a1f2a3e39cae831bc57f0c6521f95716aa98a66e6b2cfb38dddc2ca9d2f8
bunny-grid-warp-uncertainty frame_0001.exr d7230183b51ed134e83f42da7e414d3b1f3fcb1b2df61e5540e0a7b5de272318
bunny-grid-warp-uncertainty frame_0001.png e01a66f923224ad5ee0bac53a7ad456adf98a53ea1be0483a0ed7ecd8b891265
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv da6051bd0dfb48e496c0d8d82a01da4dde690dd40f43bb428b9cc1eced689e31
bunny-grid-nowarp-uncertainty frame_0000.exr 0b84c6cfec4f376abcc182b0cd4ab14295881acb98e31bc4e53666dd0a78a09d
bunny-grid-nowarp-uncertainty frame_0000.png e8a3bc559dd272aeccb7fe5fc01704dfef00be933d92056ddbeae14998a2b790
bunny-grid-nowarp-uncertainty frame_0001.exr 9a8afbd83af5a7fd7f403f9d6b4ba020e8e9657bf886aa3bc5da701be4a1e9df
bunny-grid-nowarp-uncertainty frame_0001.png 8dbd3cb660ad814f8c3d7ad4d97eecbe1c30976685c5fef45c4b38253a5bb52e
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv fd8c465b9216f174c843d130d527009f8642ff070b3b9864d49de208a77b9f3c
bunny-scan-nowarp-uncertainty frame_0000.exr 1e29ebe2c794104f653d69d53dc5984ade299079c1f4affa6f948a3af0b60132
bunny-scan-nowarp-uncertainty frame_0000.png 401fc6c96ce33cf9163a776e9ad7d8cfc7edf9c56046f9e44afe0d00ac083711
bunny-scan-nowarp-uncertainty frame_0001.exr 4753222217d377e7af451481c270bb235b4fca91b209017e7053c0e7461ba8c4
bunny-scan-nowarp-uncertainty frame_0001.png d65e4a7b22c6c2e7142a85d624e85aa1eead4f464862c87e2383ff70acbebdf0
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv 20cc516a50e12509ab9fbc198d16f8a7e5ed37e5e2e529a2f4705cace360a6ec
bunny-nowarp-all frame_0000.exr 89d4c4c3b82e9281d3781e286a83f9542a9836ce66aff904d87773b40c4313be
bunny-nowarp-all frame_0000.png 9503475e01639383cc4853e891d63968c06a1ab5b1ab3ae3cec393c1d90062fb
bunny-nowarp-all frame_0001.exr 28886b5178eb66bdf2c395ae1e47189152dafb49d91d92e9550bcff407a1f53b
bunny-nowarp-all frame_0001.png 30063c666abfc65e9e3f381892067013a6272bd0c7b016e7fff27cd1b223841f
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv 6a2cbcb96d5c7adb62a2878e475572745229f2319865b306db4d7373221342ae
bunny-nowarp-contrary frame_0000.exr cc937cb55333939f61b2ce92d415288030f4751adab3a2fc3ba11a4fead9fbcb
bunny-nowarp-contrary frame_0000.png e5477e2510a1b2adeded69402be8c33e6011226e1cc74d5a196cd6327b0e0f2b
bunny-nowarp-contrary frame_0001.exr f8cbc6b15575fa206956f758a916f244a13c1f3a55ee0e59e02e71052776f7c0
bunny-nowarp-contrary frame_0001.png e9a59bcd02c422cc29e7aead38417edf9daf4d01ab985c7d795ca5e9f306d98b
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv e4d99b9574d7ff1331da9ebb04e44af4f719af81194c9933d2d7199bbc6af237
bunny-warp-contrary frame_0000.exr fdd54a9e9c418b07d8e0cd008bbdb9d461983962b5e8465adc0a15009c9e13f0
bunny-warp-contrary frame_0000.png 9e79ef7b4c761c5fb698b619c9e2f439b10928f41badc8d362440961388d5266
bunny-warp-contrary frame_0001.exr 5fe15a218aafc37d96d084dc6095bd419c9d8962105a17c95a525a7089873a07
bunny-warp-contrary frame_0001.png 574e44f3ad7b4feda78c87f55ec7624fbacacea1ce91417556f3bc2f191d2a02
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv 18492050db107104367d377cf5077dc390752a9db8982d6fcafade61bf5bebd7
bunny-tuned frame_0001.exr 8d72418262a7cf6b58377298cbcc92e6ab62f091d021befa23bfceb19359c241
bunny-tuned frame_0001.png 5152dae6dc229f56b560ec5da0c782c7aec1f48578630f6fc0a02d1c9f4c8575
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv e8701d2de96517a69e08d5360f53e2f277b88d50524aa61a061c5d1c7719c9c0
bunny-scan-block frame_0001.exr eda209ed7e1b76496d2a32a3ad3abe2a002fed194225f666d124b8b4023ab829
bunny-scan-block frame_0001.png fc31d8715dd95eb33d953ece63fdaa73cb2075d32fe6ffebc218327914bfa0ba
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv f98ef6c8eda859fde763d085d27aae55e6456cd89010e8a05ed9c27adc32a64b
bunny-validate frame_0000.exr a1fdc3a53ae2cc223b8154cd75372ce6e416a99012593f72a152a549186ece4a
bunny-validate frame_0000.png e8a3bc559dd272aeccb7fe5fc01704dfef00be933d92056ddbeae14998a2b790
bunny-validate frame_0001.exr d975014863418b1872cfe6c5a1e6b4cae0da2e3efdf3694782f56b380b802ef8
bunny-validate frame_0001.png 8dbd3cb660ad814f8c3d7ad4d97eecbe1c30976685c5fef45c4b38253a5bb52e
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv 9d7194a59aa7b6ae0169892a89088b5cd2f550a7eb031a64e8f0ebb6367a9be1
bunny-validate-warp frame_0001.exr 653d24c047e504891288d919570cc800739a294ad471d74fb2565854b6c2a783
bunny-validate-warp frame_0001.png 257ca4da7846b2d18f95ea882803bb81075a81a189364d83b1ae105d9a3c7d5c
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 467cf7670e72521c5b48e76ff3aefb58b83e085375382580428226363cccc99f
bunny-validate-scan frame_0001.exr 09ed43ecc68c19241c4c8885866c83af0a64e672c659fefee0f6575bcb47168a
bunny-validate-scan frame_0001.png 0f77d5e210565479f10987d1ffdd530fd55096daab929fa02309457c045c87e0
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv 0a91cb5193527f9ba17ec361bb93a13c3e4012e75d0a617b85b7692e20d56526
bunny-temporal-orbit frame_0002.exr 521b27ae7bb83c0357ffd7ca5f064fab4feed962da1de83d69a4538c762fb73f
bunny-temporal-orbit frame_0002.png 27c68b99e6ec42402c6ba46b7fa144a4e1794070d88757765c31eeff01b46c93
bunny-temporal-orbit frame_0003.exr 921679f50bec92ddbe096927f8738a18730ce0e3e5d93f24ec8797cc70ba29ba
bunny-temporal-orbit frame_0003.png fc75d19c092093eb086721bacda81555be9f6353e122de4688cf54e66fe09eef
bunny-temporal-orbit frame_0004.exr 3648a3c763ef8840abce9ae0f8e2b5cb286c736781d945658b56df530c3f7ab8
bunny-temporal-orbit frame_0004.png df687467ca6748f6b41337f1048960148a86447102d9538b8d8cf4f919c3adfb
bunny-temporal-orbit frame_0005.exr fc32c2b93abfef2d9178cd3a4839893413204d3e89c5c74c9f93bf447dc587b4
bunny-temporal-orbit frame_0005.png 6a713ad7f2cfb7f1d181dd12f9a9cbe2acca9d0bb7cbaa939f3883f3d04328b0
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv f81c3fff9d387de02ddcdb21734ceb484cee9bd5220b31ad3862054aff76b8d3
bunny-temporal-warp frame_0000.exr 51212cf97def2e3ec15876224cd82970e416b85fd9638602b508e58d533b05e9
bunny-temporal-warp frame_0000.png 29c1a1f2a3e39cae831bc57f0c6521f95716aa98a66e6b2cfb38dddc2ca9d2f8
bunny-temporal-warp frame_0001.exr f6afc1a00023c38178e996310fdf847b63c92ccc09aca450cd17875838e26113
bunny-temporal-warp frame_0001.png f5f6bb0cc1d60ebf8cc4386e4ae3cfd40f80bfdb3cea7c0fc8547bb3db7ffcfd
bunny-temporal-warp frame_0002.exr c12db4226d2778f9389d1c1f2bf0d120b582f3c8fcefd5cfae6ff75d2f7764ee
bunny-temporal-warp frame_0002.png 2117fdb068bf30bddd566936b55c2d5b1d7575ceb080cf852ba32034c394ad34
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 3e7d7ced40a8121859edbf11470a184f9450cee9c22794424b93ff8aba9f00ae
bunny-brute-lambert frame_0000.exr aae92017f3646975fa3976928bf3a357762ec28166b6295acd450469c1217982
bunny-brute-lambert frame_0000.png ee648a99eb3f1b3129bab45f64dcfa09c3de1cb9711595a4ec51b1462c72f6ca
bunny-brute-lambert frame_0001.exr bde7c1bd377645a7b390eb0e2aa4617d1808af0b56dfc5cd064cadbd95badd7e
bunny-brute-lambert frame_0001.png d81e4b8d6a073bf3881c7a34f7d26cb29a3274c97c196b6d9b5016d7335b8f00
bunny-brute-lambert lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute-lambert stats.csv ecbe98428374ccf54efba77e17cae9f777d3bd21f98341a50f148580a3e62e5a
bunny-temporal-spin frame_0000.exr 676be2b893e60a07b0d15086c1e2827ed96201fb5726e73fbd72cae981514adf
bunny-temporal-spin frame_0000.png f96b6ef2a1fb6f296f32a53f1c4513fcf72631b04a5d1812bbd2ae63b9853dad
bunny-temporal-spin frame_0001.exr a26bdab4f9f8ac3bddf3e57d8d26bd42feb0a139fe0020e6a15118db112d7880
bunny-temporal-spin frame_0001.png 8c42427562ff654d0ab1c1a81b3af58cca26c8fad799b5174aaf41b766e5b66c
bunny-temporal-spin frame_0002.exr 49d6c9074bc23590cc0477a81c31833e125c2ab491a41f47970be555f894d24b
bunny-temporal-spin frame_0002.png 5184c207f2500d2dff6264ee1109c5b3e59df1c961d754dca17245827bea424e
bunny-temporal-spin frame_0003.exr 0312ee44b5e1ecc9f025f1c071d672f1ab662051fe9e8e4d455429bfe146c983
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
