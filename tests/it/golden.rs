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
/// without its `seconds` column, which is a wall-clock time, and without the `spp` column
/// added after most were recorded (checked to be the render's own).
const EXPECTED: &str = "\
shapes-turntable frame_0000.exr 6ac55b2f3bcf61bc69ceec8c754c837252f9ee37ea976d45ffdb013b64030f62
shapes-turntable frame_0000.png a1b55866535781b7c6d11b8a30fe143bccff6b185e1e53366e502f73d18862e3
shapes-turntable frame_0001.exr 4a0c25dd05d788f0fc4cafacbba744d13710b54ecb581e7310784d99a5381f0a
shapes-turntable frame_0001.png c39ce057604be8f9bcb4286cc59494e53171d661e976b3f662877271dd68ed08
shapes-turntable frame_0002.exr ac45edcc932973b5e194d7aefea5b5df8a0871ad271d7f41a6c937c241ff5f84
shapes-turntable frame_0002.png e859a5db188294af3435d825145adbbdb9cf58e71d7e9b15abaa55677ba48eba
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 6c9bf6a07586f6cb955257924cb9255647d18f46190f5d7fed02b99bf10bcb70
shapes-turntable-spp4 frame_0000.exr 07411c6d49f4f4f2b5226333218f7b9c728a60bb413ffb1f05968f163e1a1d00
shapes-turntable-spp4 frame_0000.png 2942c2f14ab8912aed5752d51108b2788b179b9e6b99b63a7009c9abf6779e07
shapes-turntable-spp4 frame_0001.exr 16398b84a1a88c9d306dcab44799f59797ce15eeb935ccdbeb86197b9485cb4c
shapes-turntable-spp4 frame_0001.png 2a7fc99de5553f0bafad735360af75a6908c85d0b5b65d86cc27d4513145be9b
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv 540850352825ebd026f88ab680b5861a893a3a7aa24461a346619bfeaaca3a45
bunny-none frame_0000.exr b8a4ff53997bfdcb17b4897e94657f0ea457303bf463161b29962caa783db3b3
bunny-none frame_0000.png 45f17607a9682e25cf877454391f28e96682c96a201f64613d18f03186345cff
bunny-none frame_0001.exr fc6598943e6cf334f60896760911225ab1797eacc1afb39849a47b0d2dce365c
bunny-none frame_0001.png 90013d3f76fcae3311806f384a8c87392e1f93f226c4cd3dcd9c53ad34cc7b8e
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv f2da642e694712dbcb867dfec49916da8b09cfe3fe737ebc55d3bea2ad9bec4b
bunny-brute frame_0000.exr e301be7cb31ed9d2e8f6237495bf7e5ced1592b2372545b154974b831175a58f
bunny-brute frame_0000.png 61b7522c44ad0dd569b22d1449ca9890c9b0cad52f413dd51222d687084c4bfa
bunny-brute frame_0001.exr 8ee57986a968d3a6018bf9eac76f7a69088c3c8fab5d572eacab8abbc1b1295f
bunny-brute frame_0001.png a8b5a1abeacf24716b31f42fc88b0caa94996e5a78de0a84a7a2aeba0d58a74d
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv dea59863af088772662dec0ee729feb3124e433f2c3d7e51e43b4e88de4d2b02
bunny-scan-warp-boundary frame_0000.exr ed4a96ba1a4c03bc736d6588c182761e2c9598b996d597538feffe46f7cf2e65
bunny-scan-warp-boundary frame_0000.png e2cb207c288c69d5fb8c2e7b49b754cbe36e44dcb32c66d7cd0570e9c7b3618a
bunny-scan-warp-boundary frame_0001.exr 19d30df0c0df89d4a43118bba1b1c0f40b62ff2cfaa311fc8d07bbba93fb6502
bunny-scan-warp-boundary frame_0001.png 3df5cef767f2b9984a8eb078429e720bee1302a67850c0d57e1f3b7be4e3d412
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 85e705dda9d8539aa40b2a17d9a47a05a5a4ec9f34ec6e2355389ed3bbabe315
bunny-grid-warp-boundary frame_0000.exr 55e120a81f8a36e7e3a8f5bef0d8889644ea78779409f39ba92de217686cce02
bunny-grid-warp-boundary frame_0000.png 77061126975da5c306221f3527113580c4ad0faf6b59256b16957207fe99b794
bunny-grid-warp-boundary frame_0001.exr b90811f8b1b71be67615577f182048381dc8b2b105fa84792ef2b2ee37627ded
bunny-grid-warp-boundary frame_0001.png f4a440adaba287a3a6e64ad6e436ba0d91a5c40101d35fc2144057c64649e958
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv cf291ceba167064918e92c442f0967c92cdb60bf701abcf7eb4e407ce521528a
bunny-grid-nowarp-boundary frame_0000.exr be2c8c43be8c05d41c5a3f1832899d7b6b4a2fea887cb29f0648a8fa82819318
bunny-grid-nowarp-boundary frame_0000.png 3ef4df07ed302bd916becdac051a11762145cd1e55e397289e49499d3eb51308
bunny-grid-nowarp-boundary frame_0001.exr 0d2072242f3a9bbe61f15b748cd57bb8f607b65219acb1c9145941d8e2c363cf
bunny-grid-nowarp-boundary frame_0001.png 5b78c2c068087d356a34c47dd66c1fd508f3f138624c8822de5f83b486b87cea
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 50ce3e753a666cfca057a41e1eac6b746e4c0121c152def0b0e6bc0c21f30da7
bunny-grid-warp-uncertainty frame_0000.exr b719cbc588a1955a0f497a4e0cf4a18c1b4fbacbbf14faa068332a63c68fc390
bunny-grid-warp-uncertainty frame_0000.png 664e9893921529ea2a60bbe01b18c2635e3dfbab4b40889f1c4913cdf9226b0f
bunny-grid-warp-uncertainty frame_0001.exr 1e6014a680ceae907e2817020a381e919f7844b16f832ab0f95734107e9fd664
bunny-grid-warp-uncertainty frame_0001.png 4fa217a29b0ebcad4a4f7a6168ed485b925dfa8e55fcfee60f009ef5c7155845
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv d204b31c9e78552d93afb35da486084fdf321244707d9259bb57391bbc29479e
bunny-grid-nowarp-uncertainty frame_0000.exr 0afdb3ead8df624724691c6ddea34ddc2458c183f36350ff40488f3aa37130a6
bunny-grid-nowarp-uncertainty frame_0000.png 8ce65c1a5d4fe8c8b4e961e164f408400daf09979d483c3594bef395bca438b5
bunny-grid-nowarp-uncertainty frame_0001.exr 9b5569c6933fd785780cb70d7429400d6b2d8722a7e461722ef7b354cc4dc0f3
bunny-grid-nowarp-uncertainty frame_0001.png 7cf78f4908ed3e825b0abce5c21d32d54b5ad76b89bc5ef8b4f814d7100a0741
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv 52dcc6b93f0df6759dc69301f316556989c104c376de0989b394ee999ec2801e
bunny-scan-nowarp-uncertainty frame_0000.exr 5636564830e738a075d7d2259ed7604be04a6f8f002572ea335bedcd072ab86c
bunny-scan-nowarp-uncertainty frame_0000.png 88e5d81943a1adf1cc956fa7fef68b5d7e9732d02cf78ad91f8eaafd3f1960d7
bunny-scan-nowarp-uncertainty frame_0001.exr b146cd990badd1496493f6ddc4aa0f2c163c4955ebe7c69bfbd35faad36f4a7f
bunny-scan-nowarp-uncertainty frame_0001.png f04e7a2c9f2593b9388cca4808ddd6e8981a57eaae5df9292e74dbd59a498411
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv b23b55384c5c4f8318636ee5cd7281cf1fdb7ae0aae4bbff66bd2cf0928c8aa9
bunny-nowarp-all frame_0000.exr af327105a18761ba2f1e7f4deb93b457367098f76847474c9d1e445ddab899d5
bunny-nowarp-all frame_0000.png c8361a5539fc7cb466430277a67717b79df825f1b81bb8b9cbca8e1e703457db
bunny-nowarp-all frame_0001.exr 18926623061a8b648e9bf29d7e346451ee96bafd237df5667b112b8baccdf1ae
bunny-nowarp-all frame_0001.png 584a77f8de1598b8dccd6b3bfca59efd4ac42861057fdb84e0c70c8c140e6592
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv c35dbd5906f633061660959526fd7e00ddd26c47b7440d557fc9cc0240f7d76e
bunny-nowarp-contrary frame_0000.exr 151980acebc4c9b899b7282254dd25ec10d8e58900518d8e438f4aee28c31a2d
bunny-nowarp-contrary frame_0000.png 41009cfe59783ebf141af1720accc07bcda4c7b9373844f01928664d424c717f
bunny-nowarp-contrary frame_0001.exr 6e6eb736d9c3ff534a3076adcd4b25c1b6a8747a84fb55c8e5b43ab5a4762240
bunny-nowarp-contrary frame_0001.png e6c46e231c3500e79e16f488c6ff4155b07300cb400797aa0ae7e5676f37741d
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv 68d99b20ceb44db79e87162568af23ee9af87e41026a427be6a13feb96ad0395
bunny-warp-contrary frame_0000.exr af45c987ffb35d84e2e99c6343221b713e048d95cf067099afb38250cf00c27c
bunny-warp-contrary frame_0000.png 38ae4e2b3002c7f9f6c7ed9590676e71f9db15e1172ef05737f369f9758f3be8
bunny-warp-contrary frame_0001.exr 4f2cebd94ccd692977cedbb8b75e68d2bb094713bcd00152a485a0b50c561888
bunny-warp-contrary frame_0001.png 0935b2cd47320acbe279b82afbd1215c64ce20d08a4cc504f167acc2dfa7dd18
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv 6a80d3d5122f34b66f6d1c0a198f92c5d4d97e296a99ec8d2a70bb147d51406b
bunny-tuned frame_0001.exr 85a137caa133ab2bc022122e0c1c2ba29eb63def28834f0f5054bc65b1f58120
bunny-tuned frame_0001.png f338f026f092b4ffd1ce3be9b7562fc1ba3516ca73d519c9525c3e65a5db9958
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv 2722223dd2135845d95cc8878a62403f7f49961127b19f511b00e56a0cb0792f
bunny-scan-block frame_0001.exr 2187f2921369c3053bc4be36050ea14b4a2c4cfc1be0504418a2692cf88e87ce
bunny-scan-block frame_0001.png bfebc22b48fcaabc5b845eb34e81f1799b9771cc7c06a6df330c1102ceab6305
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv 894fdcd38d971118b4fc635b79a56626e20f72f00a72d065dee8f05017b2d58b
bunny-validate frame_0000.exr d22529e6601fb2197e6105643f92accb74e7850bee04e71b001f623307133bd8
bunny-validate frame_0000.png 8ce65c1a5d4fe8c8b4e961e164f408400daf09979d483c3594bef395bca438b5
bunny-validate frame_0001.exr 7e7099d984adac095ee050f9a5596c82d2683bc08b523e56d68a37ce57ee81b0
bunny-validate frame_0001.png 7cf78f4908ed3e825b0abce5c21d32d54b5ad76b89bc5ef8b4f814d7100a0741
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv 7f41295b4630ad284cbe6944cdd0f91b215758ae409b1c7ffcab0c257dbb7807
bunny-validate-warp frame_0001.exr 9766ad93232b8fdf08c5bd9dc7724ecf6937aa2785e13613c7b6aaccb120ac35
bunny-validate-warp frame_0001.png f4a440adaba287a3a6e64ad6e436ba0d91a5c40101d35fc2144057c64649e958
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 03e9bb11fe3f18e39d082561ad389de189ae4591cd69a5f08aadcd1de9bea2a7
bunny-validate-scan frame_0001.exr 2446f5971ff0e8dcb41ec8aefecbffcd8437dc54a91f90c26d1cc45b312e1cef
bunny-validate-scan frame_0001.png 3df5cef767f2b9984a8eb078429e720bee1302a67850c0d57e1f3b7be4e3d412
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv d7b0c6af64cac228219ca0771d822f424206cf242c9ec3d5e75bc810c02a3972
bunny-temporal-orbit frame_0002.exr face9352aacadaaea1bc2c08e0f6603f7cdf0223d57c01da50dd91fc853b3864
bunny-temporal-orbit frame_0002.png 6c39127120cae20af9547ac75d2d102f534dacf96ad7dcf88525ddf83fe534bd
bunny-temporal-orbit frame_0003.exr fc62b252aaa3effa56082176c86829f9bd5ac47acc2f22c71ad23a642295e538
bunny-temporal-orbit frame_0003.png 0642f20d59c3c3b074f2302ce5a02e0efa40c4e09567feee208f0ea54d43529d
bunny-temporal-orbit frame_0004.exr 8ec21c5e957968f652d9386b47e36d22d76675885a18b2670f3d8c9a1dca2ac0
bunny-temporal-orbit frame_0004.png 56a531b3f6c86fa7174ccbaa4575a37112c2810a7cf766271846ec25bb43729d
bunny-temporal-orbit frame_0005.exr 9e1ee534eadbfdc3ea2c56b8a7d3efe5d4bc80d377e5881a8537bbf51ef4a96a
bunny-temporal-orbit frame_0005.png 8cc70aa66a96a82aad6b28e6a42f67c957350d116deb440a98bd6d32d42860c3
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv 48c3aed648eeb399a7a9c6528e63e9e679335dffd41fd4e610dc7755ade9787c
bunny-temporal-warp frame_0000.exr da6e16bda5da7cbfafbe5a39f47177ca136458bb9cd020cebf9c64003dbbdb1d
bunny-temporal-warp frame_0000.png 664e9893921529ea2a60bbe01b18c2635e3dfbab4b40889f1c4913cdf9226b0f
bunny-temporal-warp frame_0001.exr fdb5cec4676d22f533b178f3066b47325d4b6537cd5d175f3a9aa2408f26739c
bunny-temporal-warp frame_0001.png c38b98754fa92c2a03313c18cda0bbcac00c8b5a76207d2b58770319e0492722
bunny-temporal-warp frame_0002.exr fb6f2add10b6ae55371ea00394d7c7710edfcb38d5608dd57297f4be93ba6762
bunny-temporal-warp frame_0002.png 5e76129bd64d4cd54634c5331edce54d5bec369d1b45877af707bf5e42fd38f8
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 5ec83275df1b4d20ac5e883b5d27caf1c1b80db1cb4ef9b89c5f41b980fd39a0
bunny-brute-lambert frame_0000.exr a5928dbd413a4012c15e56b5523b481bb779e73a8a051b102239583dd5884ee2
bunny-brute-lambert frame_0000.png 7398302023a4b669825693b701c6ae85b51374ffb44ea1575683c2c5167fea08
bunny-brute-lambert frame_0001.exr e78d69cc96788ed6a23e429ad101f05754db49bc88498e18d1a7019f730bea36
bunny-brute-lambert frame_0001.png c5c31e94ee44646b360f042f9c3fdf65c5ae4e2ef0d3ab4c4265643c319d61c2
bunny-brute-lambert lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute-lambert stats.csv dea59863af088772662dec0ee729feb3124e433f2c3d7e51e43b4e88de4d2b02
bunny-temporal-spin frame_0000.exr 9402830df118aba0e5607488fd90ffc1f9f79b6e0688b9660d4139ef210933df
bunny-temporal-spin frame_0000.png df6a77574f1ed6b0d026755cd75f623bfed7ae3d4d4bc81eee88d673fe7a0e62
bunny-temporal-spin frame_0001.exr d6b83dd782a6048cb349ac39162fe1881448b4d2aa77e85542d6ca20259d5a6f
bunny-temporal-spin frame_0001.png a0031dfe5e1e0540d779124d5afb4eed69d40ad45496fa56153fc6e9301f74fe
bunny-temporal-spin frame_0002.exr 07c1f2ba72999769ddc6b092dfa7711fbd326ef97f74de5963cf2613e5d448c9
bunny-temporal-spin frame_0002.png a215fa1175e288a6e68d2845b213f2c6661e95dd20e77a5bcb58874b7812ce4e
bunny-temporal-spin frame_0003.exr 7e3f23c065936a215cb91809300641a564a2a887f9f83c7df8ed4c232f684c9a
bunny-temporal-spin frame_0003.png 8c1f60f827005d1a7ba77c3e7c746170e3abb3a479d129b417fc98f35184eaa8
bunny-temporal-spin lights.json 103f720aa426b7ad9ed05f0b47b0a7d9096a5429b996d950aa4e62c981aa7cd5
bunny-temporal-spin stats.csv 656dbc37e58e4887cddc2e229a81e62d9ba5ac4dea6ec0c47ce10eb2757f392a
";

fn sha(bytes: &[u8]) -> String {
    format!("{:x}", Sha256::digest(bytes))
}

/// `stats.csv` with the `seconds` column emptied and the last column, `spp`, removed once
/// checked to be `spp` everywhere.
fn stats_without_seconds(text: &str, spp: &str) -> String {
    let mut lines = text.lines();
    let mut header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "seconds")
        .expect("stats.csv has a seconds column");
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
