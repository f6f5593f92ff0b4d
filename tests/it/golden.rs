//! Frames that must not change: the SHA-256 of every file of a fixed set of renders, recorded
//! before the restructure of issue 25 ("one direction through the renderer"). A change that
//! moves code around must leave every frame, AOV and count bit for bit as it was; a change
//! that means to alter the pixels updates the table below on purpose (each render is its own
//! test, named after it, and its failure prints the render's new lines of the table). Updated once on purpose since: when every transcendental function on the
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
//! And once more for issue 38's shading rate: every EXR header gained the `[render]
//! shading_rate` setting (its pixels unchanged: `idiff` finds no difference against the
//! previous build's), the four-sample frames render at the sample rate as before, and the
//! pixel rate, the new default, has renders of its own.

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
            "--frames 0..2 --spp 4 --shading-rate sample",
        ),
        // The same frames at the pixel shading rate, the default since issue 38: Lambertian
        // samples are shaded alone at either rate, so their files are the sample rate's but
        // for the EXR header's `shading_rate`.
        render(
            "shapes-turntable-spp4-pixel",
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
    // The bunny's glTF material shaded once per pixel surface, validated: its reference
    // shaded the same way from the traced bits (issue 38).
    v.push(render(
        "bunny-spp4-pixel",
        BUNNY,
        &format!("{SMALL} --frames 0..2 --spp 4 --validate"),
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
shapes-turntable frame_0000.exr 1535bcdca3b85c15c0d61c3e7ade641a048397624343aee0a46ec5ce4f95dd63
shapes-turntable frame_0000.png a224c23a0a67bdde36a9afa00c9f58cd95e3b66271fb4dae0ad15df597c8350d
shapes-turntable frame_0001.exr 2f17d566538ead49bcc58ff1f1e67284708ea4ae744e85266f462641b43129c2
shapes-turntable frame_0001.png 79b38b1d83ba53694d48fa986105d19af6b3b05f2a97f81453613dbcbc51e298
shapes-turntable frame_0002.exr 5927d4bfd03899f5ade1b31976e20cccda4bb907112c06b141e650ca8471d417
shapes-turntable frame_0002.png 41e9dc7d8089249e81fedea5659615b0fa6a0b9bbd25c382623c2791564f66bd
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 584ab9b6a089803f383b6482affaf7a05e653c05e11f073e9338716f19c2f3c4
shapes-turntable-spp4 frame_0000.exr ed273e417d74f612e0e94c542c340bf7fcc93524eec99e3a21964df3317b3edb
shapes-turntable-spp4 frame_0000.png 925a221a83189795cc97ee9ee9eb13083026dd7e6493f3489ebfea93696cd18a
shapes-turntable-spp4 frame_0001.exr f36c5121e35e7732bfe8d0239703e5ae4f60c4a957781a8c81c38b1365719111
shapes-turntable-spp4 frame_0001.png b3722e79f035de93f7ad4bf3f113afc58a4f7a1547c22908e18d50ddc4aa8092
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv 28e8f2955139f9f977b0681f4fbff2373ddceead83a742dc8a3278ab35ca9c88
bunny-none frame_0000.exr c324f438cf11d71910586633e8ce3ab17105a7d8612d61e11e1e5d3096ca65c1
bunny-none frame_0000.png 5c8adb6e81fb90ed044a07da50cd02c56685173c2d7188ce17b1b13de266ba92
bunny-none frame_0001.exr e7e19be02f399e57aa6aeefc2d6055c37ad089eac2f7af43bad548df414e150f
bunny-none frame_0001.png 2d759d47bd1032cdc8d6cd608cdfe0cf217ed1cf63848a44f22ff386c633ecbd
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv 6e510901dc76613908351c14386be10a384c9f45258bd7d1c69e30f8e90ed6b1
bunny-brute frame_0000.exr 62994bad38826127f3103139378b9159a4a1ab5cc6ecd12a51aaaab6f4976658
bunny-brute frame_0000.png 5bb9d3ceb17143439bef0b2844e7f9ef8af4c889a6becd7fdca9adb0074cf666
bunny-brute frame_0001.exr 9faf0dbf2b31849dcd840a27927b584fe6966f194f4f5a136e4ae2b514d0dea3
bunny-brute frame_0001.png 0adb81829f5acb436585afdc09b8450f3e13d5dcbabb6081cf5d49e1a5951e1a
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv bda14be74b3713d2a4d0d3c87571c53554e17c0577482ffa60cb330777b1dd8b
bunny-scan-warp-boundary frame_0000.exr 24c763e19238396d23010095d5e20e061c9ddc3ecdbeeefa98060e9b3277d11b
bunny-scan-warp-boundary frame_0000.png d089f3139d3fbc9e6281d4c268bf904c474b51b7e6afcfd85bbbd40779e23e5a
bunny-scan-warp-boundary frame_0001.exr deeae73f771b01e4df6be2f38d7684f93f26e1001512f22f454e66070af09a38
bunny-scan-warp-boundary frame_0001.png f9f407a7c951123bdde03b6acfd7522284021863f87a35fe9c9eecf82e8c17c2
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 0aa510e61dc04bce48df45c674fcb2130abcb7211af6b9f4a74302d6f7cbfab9
bunny-grid-warp-boundary frame_0000.exr cec0cfd22e6370b038a3e845825aa27a6be443aaf2c2ba732c754a44cc420035
bunny-grid-warp-boundary frame_0000.png 84e94450775d2f05e995d6f2cc29bf57e34a5d89625c125bf86b33f9d36ea814
bunny-grid-warp-boundary frame_0001.exr 1bdb419a9eea847fdab6a917ef858d147df71271228de5d17df24a2635f42104
bunny-grid-warp-boundary frame_0001.png c06a9184467b0700d20c1d04124c46c68bc5888e59fb79fec893c8d1586203c6
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv 0ac9a4d578fb3380c5092ec9565b64e8e269bdc524edd31f214f5c05ff5d978e
bunny-grid-nowarp-boundary frame_0000.exr 394207ad67170ed88650d123f6f7595ae65790d8928d8ec358613b9b6896e507
bunny-grid-nowarp-boundary frame_0000.png d44956c201ad86134e6b199785cc968aa19e02930cad371ef3643ebbc12f8edf
bunny-grid-nowarp-boundary frame_0001.exr cf1d0f376ddaf2709a6db3c3d269c2ca2b20f12fb288e6e229326de4e0d245d6
bunny-grid-nowarp-boundary frame_0001.png 97fc947d5ac6e207f132f597998dbc4d49635f29807a865d32e2f0cd92b44397
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 3875c8aa53546b0d7acdd48570ca4626d3c9853fcaac886cb45a30182b04ef03
bunny-grid-warp-uncertainty frame_0000.exr 513c50afba31ed65bffb19b9f881e0f750a83849cd5f117efb75940d55303d08
bunny-grid-warp-uncertainty frame_0000.png c5f22d08312cf4ff8007ff2d7dd416e4293c4b76ec7786033f3c098f084c5cc0
bunny-grid-warp-uncertainty frame_0001.exr 48810ba9ae5cfed54c8c38092ea16f5ff4859dfa2b69715e8ffe4525e65913fa
bunny-grid-warp-uncertainty frame_0001.png e35621e6bc5e04ed1d740ae481f491b5ff5df299157ab012b4175c6cf305c511
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv d6cd475c00b28067fcaf86a5160c1a7415b3733e9b99ecff3a90dab2e363d973
bunny-grid-nowarp-uncertainty frame_0000.exr 4bb5b578a723589605410de7fd9209ef0cb141734a8ff6ae6d01868c11511b0f
bunny-grid-nowarp-uncertainty frame_0000.png 96c468ba5c30213591ae37d32d8585d9462297958160f4b05e9607df1a74368b
bunny-grid-nowarp-uncertainty frame_0001.exr 3572debb3a8de22711dc00328933adbbbc2749fd2c039b7c6781491ba25af32d
bunny-grid-nowarp-uncertainty frame_0001.png 6d696f9bb70f129d2fd19e79b9215238733333723fb459b6311d262967588f52
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv 3702dde1e172a9698fe45193300aca5fbcc730b4a0973c1bad8c1dff3f612c20
bunny-scan-nowarp-uncertainty frame_0000.exr ac320f43f73de40262abac7d8dfe9f65fb857c402f1c0d857c08ed2cbb4d62b0
bunny-scan-nowarp-uncertainty frame_0000.png bff9b01473d5c4a9c26a277652e5b9284618beba420d60a58b9c6ef441a10373
bunny-scan-nowarp-uncertainty frame_0001.exr b55005c09c58a87c94bbdd4a190412366e9aa6f1a8f43d52e28cfbf1b0f0a89d
bunny-scan-nowarp-uncertainty frame_0001.png d892fca67e81c35218d6b226945085e0a690c7962ce3d6dd362593221f63c1da
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv c3ed3a4ecd87226c8fe481fe265aa2723bc71f2f2d1eec0ad7751613747b2463
bunny-nowarp-all frame_0000.exr 93d3d7813467faab91b65ccd519cf9c5458cf0557f21e72718445a102d09b83a
bunny-nowarp-all frame_0000.png f8334f008ee0e5d68de1f8a218a363e32b7b813fed58653805eef777d4b328b0
bunny-nowarp-all frame_0001.exr bea231a5832a59fec322d6a54e2995d6970f0e73f04d1540a4ec410a0aabe12a
bunny-nowarp-all frame_0001.png 9929374a3192660aaa0af73f3fd1d338f81c1ed0eab106571716385cedaa5efb
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv 75e46ee9b6599259b69a6ec4f8b67e6cd52d7c4e2abd206a0f077d5f8d6ed563
bunny-nowarp-contrary frame_0000.exr c3a427633e1d52d43ff5adc1ff3fa26a8a9bcc62c5c17caa03f7fa7b965c8cd1
bunny-nowarp-contrary frame_0000.png b21221818dfd251f52f46fd3cfbe07213f0e49f5fbd7bb9655973566c22008c7
bunny-nowarp-contrary frame_0001.exr bcb9fb4bce658c7ae56a109e6d24308e46e3792940f162040c2f14eb5976feb4
bunny-nowarp-contrary frame_0001.png 88663183c673597b59192dfd3651647ef28d70470b05e6fdb869948bcec181d0
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv 74c18aff8756766c281cc406f92501a389c483cc70f2db0446bf36897cccefd9
bunny-warp-contrary frame_0000.exr 328efd9c148ab86173508bc262562bcaac99f8ce7362b1c8445055c3ef8f38e4
bunny-warp-contrary frame_0000.png e49cb5547370322c1ce9412b5de46e6bbced493f048c13dae55ce365bc137b7f
bunny-warp-contrary frame_0001.exr 4f20129bbf3da853312d3ff3a54a63efdb23ed153812a0e3d8d874fee56475ee
bunny-warp-contrary frame_0001.png 3814f75d28c349b7ed7dfc6e26ba640cd96342c58d390efabb1b4f53644259b2
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv 57b1b0819ef36f2959e80e2af2f8fdf588dd552704f6717819dee361b7a49e07
bunny-tuned frame_0001.exr ba0df67bedae2d38470e8183aca8cfe355f34c3825a2275284b38561403b306a
bunny-tuned frame_0001.png d2315cd9e0fe95c3c1f64e80cc4953facc9d7b8288f151267f37e73b7b18ba46
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv ece81cd1d441dd210fd102305b75afa7aac41ea3c2660c7ee9e068e2eba0d227
bunny-scan-block frame_0001.exr cfe7cbe6829071c1321113f8291ee14e777b03912b4d2c72d264d726a6c2f639
bunny-scan-block frame_0001.png 1ea7deca941ada37d2e726b0c99662ebd899d08635356a69200ca56b06958322
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv 68f1a45f2f30a68dab8972aa4ff8e065e9c92a7b351b97b9e82a414ba962a19e
bunny-validate frame_0000.exr 0aad489323019aff15fce66c4b42d7032636afbd86059e17a51b2b3622510d04
bunny-validate frame_0000.png 96c468ba5c30213591ae37d32d8585d9462297958160f4b05e9607df1a74368b
bunny-validate frame_0001.exr bf3fea198918b62867c5b033c19d7b6e1731b9ab3a7a5ee8f60b137dd0243810
bunny-validate frame_0001.png 6d696f9bb70f129d2fd19e79b9215238733333723fb459b6311d262967588f52
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv 53c3c4acd0d44b167bc83a9150c699c0b528ae460abbddf31eb43aa65d8a887a
bunny-validate-warp frame_0001.exr 8f08dd8edc6a93f36c490b3c09154d645215688c07149d6edb7b92e83bdb48e3
bunny-validate-warp frame_0001.png c06a9184467b0700d20c1d04124c46c68bc5888e59fb79fec893c8d1586203c6
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 0dc9c2cec50c659d945357cb6c87ea98913379a16e794081be70e6d99ac5d9ab
bunny-validate-scan frame_0001.exr 24e70cfba70afaba0c780a20ece87e7dc4cfee0495fe51ac8c80346cc650c078
bunny-validate-scan frame_0001.png f9f407a7c951123bdde03b6acfd7522284021863f87a35fe9c9eecf82e8c17c2
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv 611b519a3ec069494b6f47aa36750104bcb96349bd70b743f3a8adecddbc8717
bunny-temporal-orbit frame_0002.exr 27dc555e641fe6302fc3d451cc59bb01ae0436f674264d1d70a2679ee7e4e7c0
bunny-temporal-orbit frame_0002.png 290c49b63f9de751a467b83a0b9ea89f2984286d07859a6d63fa7e1482c9da99
bunny-temporal-orbit frame_0003.exr fa5a9273486d51497a55db858440803ee398317ba63568ae1e88412009ab843f
bunny-temporal-orbit frame_0003.png c1acc3199980c829d32c5410de02383f13cdf3530511d70fef99a0411f6c78c1
bunny-temporal-orbit frame_0004.exr 0df8a7d7faff78dc07648ffdf17b7b67778a087873765b02cabcb3107603f190
bunny-temporal-orbit frame_0004.png bafd451d0eac8b43a1ab2e81f403ae9bb8ae126ff4ab93fdd4f663a60aa22925
bunny-temporal-orbit frame_0005.exr 88c56387146e31493901d2db3ed42e9f899efd24d4bbbc8c980752fd271d2906
bunny-temporal-orbit frame_0005.png 7d57ccc780095f423ae543a73b136ba4f718412b4867c7c665aeb59a6cd88747
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv c906cef420ea35c423610a1d8f5f6f94b7ab7eb0bca7d5114af70a6cb789fe7c
bunny-temporal-warp frame_0000.exr 2c7cd37310a444b290d4080d3b8a20304a85d5bdd12683a5b3b05fa1326fa6e4
bunny-temporal-warp frame_0000.png c5f22d08312cf4ff8007ff2d7dd416e4293c4b76ec7786033f3c098f084c5cc0
bunny-temporal-warp frame_0001.exr ac7f1e7b5f59d2cd5c7d6d011bbd649b4cd19d4ecf70cd4e4e45f1e8f0e8a97c
bunny-temporal-warp frame_0001.png 4d68427164363ae1f9759d7648a5281f5051d692fbfef320d73f4ec0157bc35a
bunny-temporal-warp frame_0002.exr d2f7738aeb017f25c6fc840a8a8d4630f12cd72485485e469021b677f6447480
bunny-temporal-warp frame_0002.png c82d3b8bb136806c085914b7e1ac9684b2c74d3af1df406ff451d57e3b006923
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 1dd565b33550fa90e90f4fffd943a45bd6228a43fe48b471d7f4a8d8916d2825
bunny-brute-lambert frame_0000.exr f2a03ad92adea5f884f39cbc23e6943dc75221e1a506dd7f24090c87dd317b39
bunny-brute-lambert frame_0000.png 547a94ed5847699f1486d0963bdab23e9746a4c5540601e12a86247e73a62091
bunny-brute-lambert frame_0001.exr d44c818756dfa1fe5393efdacfabbcd66e909f48a271d8d077bd9b384b0ecfc1
bunny-brute-lambert frame_0001.png 244623964bfcb448b615d45fae15d72f846d52ac1da280b53d59ae5b350a5cb0
bunny-brute-lambert lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute-lambert stats.csv bda14be74b3713d2a4d0d3c87571c53554e17c0577482ffa60cb330777b1dd8b
bunny-temporal-spin frame_0000.exr 37e4fcd5e64b4df8f9f3ba07b3ad154dcd82dd2e32fad99775eebd96d0d44f97
bunny-temporal-spin frame_0000.png 33bd6555fa6fb95b762ab6e8b83c48912af3984bfed5b74a069b12fad3e53941
bunny-temporal-spin frame_0001.exr b4d554198b9e0f6cbff7abd051df7ed0fc0fa718413244f9fb88a62d82264df3
bunny-temporal-spin frame_0001.png bbc9747d9723e7297161689e0f05bbe799f3557eca4ddf850db6f230643cfe3a
bunny-temporal-spin frame_0002.exr 5e7dbe740e5a66f6a0c3089c7390e861989069e1c36f43775779e0cf937facbd
bunny-temporal-spin frame_0002.png 238e56ffbb8fb73e56e51e3e340a782328abde4f955871d70d02120d7ab233d7
bunny-temporal-spin frame_0003.exr 8cf2b032dce2e72a3886ecba4b7f3a2b2da9b59840a62b6030026811aa160329
bunny-temporal-spin frame_0003.png cb4f0c088631d2903d16f280630ab8c1f4da9f8ece1a437ae270a6acac6d3e15
bunny-temporal-spin lights.json 103f720aa426b7ad9ed05f0b47b0a7d9096a5429b996d950aa4e62c981aa7cd5
bunny-temporal-spin stats.csv c3d25748ef7c1b6f00218f45143bec2062bf398e9bf5312ce773c84454edd07e
bunny-spp4-pixel frame_0000.exr 100d853a1a43204a3630c6c6490facb2931a3c30203c78d3b927bb04ea002dbf
bunny-spp4-pixel frame_0000.png 61bef04c66fa6235ffb5c487124737bbdadd23cf8ee314c67572b2b0e913153a
bunny-spp4-pixel frame_0001.exr fe60bf60088ca3467188076eb48691153f84f46af607d5723d91bded9c978287
bunny-spp4-pixel frame_0001.png 838e4a5ab2fb260a4ab9c868b86a0fab8cefd1ebd38dcfe2e7e709d6d3b254fb
bunny-spp4-pixel lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-spp4-pixel stats.csv 4f35536a97096acf7a9fbca8d5af45b77d17bf016ffb4289e29960d43caa7546
shapes-turntable-spp4-pixel frame_0000.exr 41239b9446b444d1e0f58c8aeaddeeb8c952b178eedcfe2e1091034d523e1f0f
shapes-turntable-spp4-pixel frame_0000.png 925a221a83189795cc97ee9ee9eb13083026dd7e6493f3489ebfea93696cd18a
shapes-turntable-spp4-pixel frame_0001.exr 87fee790cc0930b2ae4d8fe9cca03e51bf83580e7f14b69c820d93a01b69fdcc
shapes-turntable-spp4-pixel frame_0001.png b3722e79f035de93f7ad4bf3f113afc58a4f7a1547c22908e18d50ddc4aa8092
shapes-turntable-spp4-pixel lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4-pixel stats.csv 28e8f2955139f9f977b0681f4fbff2373ddceead83a742dc8a3278ab35ca9c88
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

/// One `#[test]` per render of [`renders`], named after it: a render that fails names itself,
/// and the others still run (in parallel).
macro_rules! golden {
    ($($test:ident: $name:literal,)*) => {
        $(
            #[test]
            fn $test() {
                keeps_its_bits($name);
            }
        )*
        /// The renders the tests above check, in the order of [`renders`].
        const TESTED: &[&str] = &[$($name),*];
    };
}

golden! {
    shapes_turntable: "shapes-turntable",
    shapes_turntable_spp4: "shapes-turntable-spp4",
    shapes_turntable_spp4_pixel: "shapes-turntable-spp4-pixel",
    bunny_none: "bunny-none",
    bunny_brute: "bunny-brute",
    bunny_scan_warp_boundary: "bunny-scan-warp-boundary",
    bunny_grid_warp_boundary: "bunny-grid-warp-boundary",
    bunny_grid_nowarp_boundary: "bunny-grid-nowarp-boundary",
    bunny_grid_warp_uncertainty: "bunny-grid-warp-uncertainty",
    bunny_grid_nowarp_uncertainty: "bunny-grid-nowarp-uncertainty",
    bunny_scan_nowarp_uncertainty: "bunny-scan-nowarp-uncertainty",
    bunny_nowarp_all: "bunny-nowarp-all",
    bunny_nowarp_contrary: "bunny-nowarp-contrary",
    bunny_warp_contrary: "bunny-warp-contrary",
    bunny_tuned: "bunny-tuned",
    bunny_scan_block: "bunny-scan-block",
    bunny_validate: "bunny-validate",
    bunny_validate_warp: "bunny-validate-warp",
    bunny_validate_scan: "bunny-validate-scan",
    bunny_temporal_orbit: "bunny-temporal-orbit",
    bunny_temporal_warp: "bunny-temporal-warp",
    bunny_brute_lambert: "bunny-brute-lambert",
    bunny_spp4_pixel: "bunny-spp4-pixel",
    bunny_temporal_spin: "bunny-temporal-spin",
}

/// The recorded table as (render, file, hash) lines.
fn expected() -> Vec<(&'static str, &'static str, &'static str)> {
    EXPECTED
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(' ').collect();
            (f[0], f[1], f[2])
        })
        .collect()
}

/// Every render has its test and every recorded line its render: a render added to
/// [`renders`] without a test, or lines left in the table for none, fail here.
#[test]
fn every_render_has_its_test_and_every_recorded_hash_its_render() {
    let names: Vec<&str> = renders().iter().map(|r| r.name).collect();
    assert_eq!(
        names, TESTED,
        "golden! lists every render of renders(), in order"
    );
    let orphans: Vec<String> = expected()
        .into_iter()
        .filter(|(r, _, _)| !names.contains(r))
        .map(|(r, f, _)| format!("{r}/{f}"))
        .collect();
    assert!(orphans.is_empty(), "recorded for no render: {orphans:?}");
}

/// Renders `name` of [`renders`] through the binary and compares the hashes of its files with
/// its lines of the recorded table.
fn keeps_its_bits(name: &str) {
    let r = renders()
        .into_iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("{name}: not in renders()"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    let assets = common::assets_dir();
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
    let got = hashes(&out, &dir, spp);
    let table: String = got
        .iter()
        .map(|(f, h)| format!("{} {f} {h}\n", r.name))
        .collect();
    let expected: Vec<(&str, &str)> = expected()
        .into_iter()
        .filter(|(n, _, _)| *n == r.name)
        .map(|(_, f, h)| (f, h))
        .collect();
    let changed: Vec<String> = got
        .iter()
        .filter(|(f, h)| !expected.contains(&(f.as_str(), h.as_str())))
        .map(|(f, _)| format!("{}/{f}", r.name))
        .chain(
            expected
                .iter()
                .filter(|(e, _)| !got.iter().any(|(f, _)| f == e))
                .map(|(f, _)| format!("{}/{f} (missing)", r.name)),
        )
        .collect();
    assert!(
        changed.is_empty(),
        "{}: {} file(s) changed: {}\nits new lines of the table:\n{table}",
        r.name,
        changed.len(),
        changed.join(", ")
    );
}
