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
shapes-turntable frame_0000.exr d915d0f313837f29dae20d5e221a0084cd00ded1c6a642b3394c0537017ad4b8
shapes-turntable frame_0000.png a1b55866535781b7c6d11b8a30fe143bccff6b185e1e53366e502f73d18862e3
shapes-turntable frame_0001.exr 6dbed81b1142a713b4a6700843c8ab33417724821fb3c6eb898ccab9fe879c8d
shapes-turntable frame_0001.png c39ce057604be8f9bcb4286cc59494e53171d661e976b3f662877271dd68ed08
shapes-turntable frame_0002.exr 6934def0e9a69c95c18d7141237f75328da7fe67ac2da1b73e7299f7a67b1565
shapes-turntable frame_0002.png e859a5db188294af3435d825145adbbdb9cf58e71d7e9b15abaa55677ba48eba
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 6c9bf6a07586f6cb955257924cb9255647d18f46190f5d7fed02b99bf10bcb70
shapes-turntable-spp4 frame_0000.exr 77d23214b5895560dc43281941bfc2999af2a4683db337bdc06f33004fca79f9
shapes-turntable-spp4 frame_0000.png 2942c2f14ab8912aed5752d51108b2788b179b9e6b99b63a7009c9abf6779e07
shapes-turntable-spp4 frame_0001.exr 54d6e042b325a27babf4b93b093293a84346b9186319a2228258507b29a99358
shapes-turntable-spp4 frame_0001.png 2a7fc99de5553f0bafad735360af75a6908c85d0b5b65d86cc27d4513145be9b
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv 540850352825ebd026f88ab680b5861a893a3a7aa24461a346619bfeaaca3a45
bunny-none frame_0000.exr f53c4e22df53eec7603cdcd327beea2c6c68a9cb0815f14fe336dc453dfeef93
bunny-none frame_0000.png 7e7ef97896893361ce42936ec6bdc3d866019891253a0a70732e2860ac4cf50f
bunny-none frame_0001.exr e8ebd3bb08f2ca34029b84bcf97d5e78fbd0c967d752b8692eb92e50bbf71219
bunny-none frame_0001.png 579e52dde1d36194e09edb1d97d8e21b012d5494968fa6645d57403ac766235d
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv f2da642e694712dbcb867dfec49916da8b09cfe3fe737ebc55d3bea2ad9bec4b
bunny-brute frame_0000.exr a2e74e317ffa9296159f69a4675573e38fa626f4bc4996d769bdda6366a9017b
bunny-brute frame_0000.png 7398302023a4b669825693b701c6ae85b51374ffb44ea1575683c2c5167fea08
bunny-brute frame_0001.exr 604e06b59bec693c64ef94fb8b216d1c12fe9dc0dba60bb56995714cb8e41001
bunny-brute frame_0001.png c5c31e94ee44646b360f042f9c3fdf65c5ae4e2ef0d3ab4c4265643c319d61c2
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv dea59863af088772662dec0ee729feb3124e433f2c3d7e51e43b4e88de4d2b02
bunny-scan-warp-boundary frame_0000.exr 77b5d36406ea0a0c5c16931670b4f7df7fa7b85443678dbcb51e8c3df6287e3f
bunny-scan-warp-boundary frame_0000.png 5df2c3aa025c976b0ffa2001f48dbce034eaa85692e32b2127980237c3bfd63e
bunny-scan-warp-boundary frame_0001.exr f983c231cd659670fac6305dffcd31cff6ac28c7a055d37fe5bf5903a8675c26
bunny-scan-warp-boundary frame_0001.png 1942ed96049382c3f52aecf38bed9f2f73faeaef5218d0a67bda23695e7c0335
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 85e705dda9d8539aa40b2a17d9a47a05a5a4ec9f34ec6e2355389ed3bbabe315
bunny-grid-warp-boundary frame_0000.exr e093674ec74d28c29f8360aacd2bd03ba3e1f20c3e8931901dec77f0eb20ad62
bunny-grid-warp-boundary frame_0000.png 032a0248f98419e70c0c60070d469cd578fb648d35110d61839ed3edaffb2107
bunny-grid-warp-boundary frame_0001.exr 5d4e673c3e7e82f5dfd163ebdd8e52630bf2fb695eaba02691794a6727729eae
bunny-grid-warp-boundary frame_0001.png 05801fa340bc149cd976c822dcad632785477d2aa6c52cbe73b3ef674e7c136d
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv cf291ceba167064918e92c442f0967c92cdb60bf701abcf7eb4e407ce521528a
bunny-grid-nowarp-boundary frame_0000.exr 46251d9cc15b421c1ae1ec9ca065a724496dfc01bcddc245ce171900aabf34af
bunny-grid-nowarp-boundary frame_0000.png 97cbfc91364f1a52cc2e518bef252f8d7b93a0a642a11c1985d7cfd8edfde12a
bunny-grid-nowarp-boundary frame_0001.exr 9919c7712c04e6f2af23df38ee7ae90c0cc7bc7ab8f1fccb1a197521bade65df
bunny-grid-nowarp-boundary frame_0001.png 3c70464d2464c5871a510d7c6aea30e5b8752ba12d7555daf4466a9b4242a33c
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 50ce3e753a666cfca057a41e1eac6b746e4c0121c152def0b0e6bc0c21f30da7
bunny-grid-warp-uncertainty frame_0000.exr ce6393afc2405554c2ee35796e0741dfb4adcc636ef0e54655716b58bae906f7
bunny-grid-warp-uncertainty frame_0000.png 1246f2d9bd711e064c78b288f24f703289019d500b561ebf2fe9e08631db0c13
bunny-grid-warp-uncertainty frame_0001.exr 754a46d3c0013e779125f24983cac1d13409e1823b815e6c2f364ad59ec7e679
bunny-grid-warp-uncertainty frame_0001.png 5e51da33c1ef07fc0f4da032cbb8ce3d5c96e3a1648a4b839a99e278bf743126
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv d204b31c9e78552d93afb35da486084fdf321244707d9259bb57391bbc29479e
bunny-grid-nowarp-uncertainty frame_0000.exr 40cf72a81649ea00e7b5e07011719c565cf8edb5c2c28adf4c9ce72d7ccf17e9
bunny-grid-nowarp-uncertainty frame_0000.png 236063a9ee443ee22933ca2cedd81e695d8cf76bbc2c270cae4903ce302d1471
bunny-grid-nowarp-uncertainty frame_0001.exr 2a4ff2997ca32c28f768ca995b131cbfc7f9b416cc9a5609f7d032286b063f56
bunny-grid-nowarp-uncertainty frame_0001.png 4e72fac213350e434fb0981c87730b69711a92a8ee9a42e9ef3a578d234a99e5
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv 52dcc6b93f0df6759dc69301f316556989c104c376de0989b394ee999ec2801e
bunny-scan-nowarp-uncertainty frame_0000.exr 5975d6eee40cf57cc100d788d8131f73f119e8290237b6ddd86321429a532bd5
bunny-scan-nowarp-uncertainty frame_0000.png ec965662f7e86baaff209c3bff38e8de551edb969938878548a1fc8889504e35
bunny-scan-nowarp-uncertainty frame_0001.exr d6da3b341d15f209c26cf5d7ad9dd6f93e2c6a0fce353018eb1fd56dae8a754c
bunny-scan-nowarp-uncertainty frame_0001.png c1e0274e84981ca7beb3210fd03053b319065ce9e0cb39dc25c47b5dfb0a0c81
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv b23b55384c5c4f8318636ee5cd7281cf1fdb7ae0aae4bbff66bd2cf0928c8aa9
bunny-nowarp-all frame_0000.exr cba450114557145dd6189d66fd946eebeb59e2513d7235b7205d9ee833ae9eda
bunny-nowarp-all frame_0000.png 2b3e9c1fa19a8e5c4e388086f6d9e932de269b7503796f000b5d67e69f9fa87b
bunny-nowarp-all frame_0001.exr c3e7d1e098f9fd65314a3d6c9561e1c7b68229dc9e3be95c4c4226fba5a7be51
bunny-nowarp-all frame_0001.png d062c129de4996e53fa8d31418fc44e2b201ea91d029ac275fc6b9576fcd413c
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv c35dbd5906f633061660959526fd7e00ddd26c47b7440d557fc9cc0240f7d76e
bunny-nowarp-contrary frame_0000.exr c9caa9d999dee41be6ed16dd7fc14913b98c20b9cae949136c37b34ecf6c0c72
bunny-nowarp-contrary frame_0000.png a15eb82e5ffe564afac8a354564e18f3c1add438cf2e80602432cbfb17c5021f
bunny-nowarp-contrary frame_0001.exr 2a9275901da014b48dd98c7f07389e9805938d0177201619a64c38f457bbd1f7
bunny-nowarp-contrary frame_0001.png 460abf1cfc327be7c8a67c04873ed2efb9b1ad133311e9c07b106daa23b49762
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv 68d99b20ceb44db79e87162568af23ee9af87e41026a427be6a13feb96ad0395
bunny-warp-contrary frame_0000.exr 963c8d40ba5c9e46d6208a261a9b4276e5e98f446bd3ded985fe9143f7105f05
bunny-warp-contrary frame_0000.png 3d534c7303cee1d62c189ebbbe9980267cfd73fa75d286a6d2806bc0a6988668
bunny-warp-contrary frame_0001.exr 33f70ce3dd9ff1502479d23ec65c4472597024ba4ec33b3e46c86b11a8154b2e
bunny-warp-contrary frame_0001.png 0865e12bacd879eb97486058cf6fdb9fb95562c8402d37a4bf668d8072bd4efb
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv 6a80d3d5122f34b66f6d1c0a198f92c5d4d97e296a99ec8d2a70bb147d51406b
bunny-tuned frame_0001.exr b177de76d833810bbd2e58397626ecbcbad5c6df448a789dbba28da4a6d98e9a
bunny-tuned frame_0001.png 0d480f37e987360b28100241281c889ec9c5a4669e3469d9a1ab144e79992d9d
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv 2722223dd2135845d95cc8878a62403f7f49961127b19f511b00e56a0cb0792f
bunny-scan-block frame_0001.exr 1c791ff33a6eb0be98dd06c96351b05afc7060b47204a71ff2ea1adf8346f4bc
bunny-scan-block frame_0001.png 37cdbc3a047cf2e2ff395d52ac42927b0a1795b97b509012b74eb2f16d12cff4
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv 894fdcd38d971118b4fc635b79a56626e20f72f00a72d065dee8f05017b2d58b
bunny-validate frame_0000.exr 4a9bbdd13555d690a16a201c12ea48314efc8d00fec68c6f6ef68d23bc1a2b9f
bunny-validate frame_0000.png 236063a9ee443ee22933ca2cedd81e695d8cf76bbc2c270cae4903ce302d1471
bunny-validate frame_0001.exr 1e3b80bfdcfc11e0747ff025974a7cbe478a804b2027f34d58f44c2cee6e9087
bunny-validate frame_0001.png 4e72fac213350e434fb0981c87730b69711a92a8ee9a42e9ef3a578d234a99e5
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv d56dbeef5ebfed153d13084e89a742434710e04c91591eb3b40f9c821db8a977
bunny-validate-warp frame_0001.exr 508749c23dc34c8c83883dfb57333beab2bd5c5b15eced1eb0e0c0ab329d1300
bunny-validate-warp frame_0001.png 05801fa340bc149cd976c822dcad632785477d2aa6c52cbe73b3ef674e7c136d
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 9dfed9e848ce035b959945646056982a221c6cd8c212d0303041494c6aad2192
bunny-validate-scan frame_0001.exr 175db9ca269bfba2eb1a7fb098d42f95fad6909743643840cbb82b02a76ef947
bunny-validate-scan frame_0001.png 1942ed96049382c3f52aecf38bed9f2f73faeaef5218d0a67bda23695e7c0335
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv 6ba8546b3a42d09e381fd16cf10d6aacbb91ac301adbed562f11fa7ed73c2a88
bunny-temporal-orbit frame_0002.exr 3cf2de699f110beaac2a836b9eff119eb74f124e6bc5b7678a173a692fce0a34
bunny-temporal-orbit frame_0002.png 5254d28d5279eb54eb2551251e71c68aadb4ce1faf80e5649e33ead5b510ca34
bunny-temporal-orbit frame_0003.exr aa418ced9ae6ca1eb654afe8f77dec2b53b29bba965fb92dcb97715de9891a1a
bunny-temporal-orbit frame_0003.png ce63446e3242258ac29c517f137e38063b1b6f5edf27bed5fccd15eb41af438b
bunny-temporal-orbit frame_0004.exr d1712756f1071d8b7e6e6a5c28f01f9e11fb40c0cb34a15869ae913fca3b448a
bunny-temporal-orbit frame_0004.png c658e247c793b06f13843ed43b036a2c0af223c9f617b55217ccb998fb0734b6
bunny-temporal-orbit frame_0005.exr f95c71b22a3f35d16dac97704f2052170a21afb14bc9b97c9b30bf6e7dc14066
bunny-temporal-orbit frame_0005.png a0599c4a90b878b08be000ca70281797e1c9513421aac59efad0b426c4c17a13
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv 127185c9e158e66c7cb75e0c9bf7257afefcaf13fedb727ebdd9ed9fceee5adb
bunny-temporal-warp frame_0000.exr 11139e271893ca614a7d06722e54b25e9424c48b50491cddcea18b09702f54cb
bunny-temporal-warp frame_0000.png 1246f2d9bd711e064c78b288f24f703289019d500b561ebf2fe9e08631db0c13
bunny-temporal-warp frame_0001.exr 91aa6dbdc12a736c49f5ecfed925be8d1d11d18015c71190ed665652672942a0
bunny-temporal-warp frame_0001.png 17400d0f5d7df8cc33ccfd90f993fc04ab8f36e5ffc843e790adb95dff399fd3
bunny-temporal-warp frame_0002.exr 6280415220adcc62396e2f5aec5009c4313697315ee8fbf6f526351f8f85c289
bunny-temporal-warp frame_0002.png 7d76f854bc033b0018e161547d1e6caa5d75e517c27d6760619cf1420b5a158c
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 5ec83275df1b4d20ac5e883b5d27caf1c1b80db1cb4ef9b89c5f41b980fd39a0
bunny-temporal-spin frame_0000.exr 187f20b3a537c440a35535b91d8aa8e2cd00635ef4f9ca0a90df0f46c3cb8b34
bunny-temporal-spin frame_0000.png 0d3ad9e70bb40d9a777911e8d48aec97bc41175eea87f306c962dc4d303814f5
bunny-temporal-spin frame_0001.exr 6edd56d1f72cf012dcf9ba4f27e7a884fceadb94002696fada05e051e763a09f
bunny-temporal-spin frame_0001.png de438a548f0e32a20e08dbfa5c19ef9396906c21b90d768c377e3a725cd40960
bunny-temporal-spin frame_0002.exr fb1eae8c4e7645155623f43e3b21e60cc355acb0fae41ad0b41fb5dac33582c2
bunny-temporal-spin frame_0002.png 016a9a1c635ecc04323e4feed7a6a2ccc523af595b5c90204e1d9fea72ce6726
bunny-temporal-spin frame_0003.exr be26b0e653593e25b73e07c4c69824b628dc0de9770965f7f44aa675fc3fd08e
bunny-temporal-spin frame_0003.png 00c155f2145a27c1e30e8db5333a9a548f48bef6ee87fcf2f21c60d3e004396b
bunny-temporal-spin lights.json 103f720aa426b7ad9ed05f0b47b0a7d9096a5429b996d950aa4e62c981aa7cd5
bunny-temporal-spin stats.csv 483e9f76bcf2d2cad71e8f0c26afc8bfb53f1f4198e0988e3381a371f62df78c
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
