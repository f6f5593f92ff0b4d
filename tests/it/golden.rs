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
shapes-turntable frame_0000.exr ef2056bc84ea8e268e05aac3f590c8ea537e81c6f7deac7f00923534a223ef30
shapes-turntable frame_0000.png a1b55866535781b7c6d11b8a30fe143bccff6b185e1e53366e502f73d18862e3
shapes-turntable frame_0001.exr b12a65d5561b699b417b22e44020e19d2c17caf8ecce1864fa84afd0089e0af8
shapes-turntable frame_0001.png c39ce057604be8f9bcb4286cc59494e53171d661e976b3f662877271dd68ed08
shapes-turntable frame_0002.exr 699055e5ddc606d4ffce3e43cd31c3dd4f9219c73c9fa312e45d5c82bc068323
shapes-turntable frame_0002.png e859a5db188294af3435d825145adbbdb9cf58e71d7e9b15abaa55677ba48eba
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 6c9bf6a07586f6cb955257924cb9255647d18f46190f5d7fed02b99bf10bcb70
shapes-turntable-spp4 frame_0000.exr 271dfa876aac57a83a81ea0e7884708bcc38845e2576b7d659a0456d42690970
shapes-turntable-spp4 frame_0000.png 2942c2f14ab8912aed5752d51108b2788b179b9e6b99b63a7009c9abf6779e07
shapes-turntable-spp4 frame_0001.exr 611b6c07938643e7fd52e68135119aa422142a1adb6d80fc767fc9af530369b3
shapes-turntable-spp4 frame_0001.png 2a7fc99de5553f0bafad735360af75a6908c85d0b5b65d86cc27d4513145be9b
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv 540850352825ebd026f88ab680b5861a893a3a7aa24461a346619bfeaaca3a45
bunny-none frame_0000.exr 85e0aab2df58a9ceee42a9772860408c3e98059b5a8cfbedbdf1c47f7f459adb
bunny-none frame_0000.png 7e7ef97896893361ce42936ec6bdc3d866019891253a0a70732e2860ac4cf50f
bunny-none frame_0001.exr 2b3f5889ddb69007f35a36e2e72d464cbc3cdeb58002f9624b6a07cec2487cd6
bunny-none frame_0001.png 579e52dde1d36194e09edb1d97d8e21b012d5494968fa6645d57403ac766235d
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv f2da642e694712dbcb867dfec49916da8b09cfe3fe737ebc55d3bea2ad9bec4b
bunny-brute frame_0000.exr 3a515730f7eb561012236eb3924b7bcb272286babab3457314f9d71b964f99e2
bunny-brute frame_0000.png 7398302023a4b669825693b701c6ae85b51374ffb44ea1575683c2c5167fea08
bunny-brute frame_0001.exr 48b057c8c7a372953df2a562f9868bbe97cef1ea378f56cc91ca629235905568
bunny-brute frame_0001.png c5c31e94ee44646b360f042f9c3fdf65c5ae4e2ef0d3ab4c4265643c319d61c2
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv dea59863af088772662dec0ee729feb3124e433f2c3d7e51e43b4e88de4d2b02
bunny-brute-lambert frame_0000.exr 3a515730f7eb561012236eb3924b7bcb272286babab3457314f9d71b964f99e2
bunny-brute-lambert frame_0000.png 7398302023a4b669825693b701c6ae85b51374ffb44ea1575683c2c5167fea08
bunny-brute-lambert frame_0001.exr 48b057c8c7a372953df2a562f9868bbe97cef1ea378f56cc91ca629235905568
bunny-brute-lambert frame_0001.png c5c31e94ee44646b360f042f9c3fdf65c5ae4e2ef0d3ab4c4265643c319d61c2
bunny-brute-lambert lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute-lambert stats.csv dea59863af088772662dec0ee729feb3124e433f2c3d7e51e43b4e88de4d2b02
bunny-scan-warp-boundary frame_0000.exr 0f42d62f74001badaf9e5d5eef6ebb9ff2a6f276a54a20bb37e6e6c52525d74b
bunny-scan-warp-boundary frame_0000.png 5df2c3aa025c976b0ffa2001f48dbce034eaa85692e32b2127980237c3bfd63e
bunny-scan-warp-boundary frame_0001.exr 778c9b4880c4c3afa4033f682357371f76cfacbb6a65e248a32792c46998954a
bunny-scan-warp-boundary frame_0001.png 1942ed96049382c3f52aecf38bed9f2f73faeaef5218d0a67bda23695e7c0335
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 85e705dda9d8539aa40b2a17d9a47a05a5a4ec9f34ec6e2355389ed3bbabe315
bunny-grid-warp-boundary frame_0000.exr 0ee23cd2fa9aa8ebf321e9a4ed3e0ada60ab306901239c93ca5e381e6b5e0607
bunny-grid-warp-boundary frame_0000.png 032a0248f98419e70c0c60070d469cd578fb648d35110d61839ed3edaffb2107
bunny-grid-warp-boundary frame_0001.exr 77397317605f938fd1148d218a02992cf01f14b5cdf70dbcbde3da23c4e403fa
bunny-grid-warp-boundary frame_0001.png 05801fa340bc149cd976c822dcad632785477d2aa6c52cbe73b3ef674e7c136d
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv cf291ceba167064918e92c442f0967c92cdb60bf701abcf7eb4e407ce521528a
bunny-grid-nowarp-boundary frame_0000.exr f2d520c7c7b73f8585d02c421557a84311893c49f6d47be7d0b51e2485b39618
bunny-grid-nowarp-boundary frame_0000.png 97cbfc91364f1a52cc2e518bef252f8d7b93a0a642a11c1985d7cfd8edfde12a
bunny-grid-nowarp-boundary frame_0001.exr 750bd96437b8781120106ac683cd41d6d774d11a1876872055598694ed14193d
bunny-grid-nowarp-boundary frame_0001.png 3c70464d2464c5871a510d7c6aea30e5b8752ba12d7555daf4466a9b4242a33c
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 50ce3e753a666cfca057a41e1eac6b746e4c0121c152def0b0e6bc0c21f30da7
bunny-grid-warp-uncertainty frame_0000.exr 181a3d1716c18bcc20b3720f6f7510b7f1ce664b8491e2718346a67ebe57bfa0
bunny-grid-warp-uncertainty frame_0000.png 1246f2d9bd711e064c78b288f24f703289019d500b561ebf2fe9e08631db0c13
bunny-grid-warp-uncertainty frame_0001.exr 764843725b745d2a834dbadf774035d52095bb3fc578a5fcd970ad3a6e1ce079
bunny-grid-warp-uncertainty frame_0001.png 5e51da33c1ef07fc0f4da032cbb8ce3d5c96e3a1648a4b839a99e278bf743126
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv d204b31c9e78552d93afb35da486084fdf321244707d9259bb57391bbc29479e
bunny-grid-nowarp-uncertainty frame_0000.exr 0e465d3221895f4e2e832f4264a17770b0de3d9c675fc45c9bda80270d2864c5
bunny-grid-nowarp-uncertainty frame_0000.png 236063a9ee443ee22933ca2cedd81e695d8cf76bbc2c270cae4903ce302d1471
bunny-grid-nowarp-uncertainty frame_0001.exr c7a2b5f56330b1ed99f572fc74237e533e428ec015843404f153f5c42db1a4d4
bunny-grid-nowarp-uncertainty frame_0001.png 4e72fac213350e434fb0981c87730b69711a92a8ee9a42e9ef3a578d234a99e5
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv 52dcc6b93f0df6759dc69301f316556989c104c376de0989b394ee999ec2801e
bunny-scan-nowarp-uncertainty frame_0000.exr 389bf3e8b78ecd1d8b450ad50836c4dd295249ef21a84d4b5ca0df91787443ef
bunny-scan-nowarp-uncertainty frame_0000.png ec965662f7e86baaff209c3bff38e8de551edb969938878548a1fc8889504e35
bunny-scan-nowarp-uncertainty frame_0001.exr 0091bb82d712772053d14253eb16576dab7e1db94c5b2587a0ae4a8c109a08b3
bunny-scan-nowarp-uncertainty frame_0001.png c1e0274e84981ca7beb3210fd03053b319065ce9e0cb39dc25c47b5dfb0a0c81
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv b23b55384c5c4f8318636ee5cd7281cf1fdb7ae0aae4bbff66bd2cf0928c8aa9
bunny-nowarp-all frame_0000.exr b31bc499760ddb46c1b2a0b764ba59276e84ac959eba825a7ac424008cd1b93a
bunny-nowarp-all frame_0000.png 2b3e9c1fa19a8e5c4e388086f6d9e932de269b7503796f000b5d67e69f9fa87b
bunny-nowarp-all frame_0001.exr ffc3a11ea6a3de65fc854467dfcf76b0b64566720ab00a10ac4ed9e50533e70b
bunny-nowarp-all frame_0001.png d062c129de4996e53fa8d31418fc44e2b201ea91d029ac275fc6b9576fcd413c
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv c35dbd5906f633061660959526fd7e00ddd26c47b7440d557fc9cc0240f7d76e
bunny-nowarp-contrary frame_0000.exr 6aadfb440c4c5895127cabe149211b00644c422d97aa068c02cd25b7b8be9eba
bunny-nowarp-contrary frame_0000.png a15eb82e5ffe564afac8a354564e18f3c1add438cf2e80602432cbfb17c5021f
bunny-nowarp-contrary frame_0001.exr 58e12c03f1df3fc2fa280d4bee98c12929c5c02e3a9cc9e7cc757686665d8df6
bunny-nowarp-contrary frame_0001.png 460abf1cfc327be7c8a67c04873ed2efb9b1ad133311e9c07b106daa23b49762
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv 68d99b20ceb44db79e87162568af23ee9af87e41026a427be6a13feb96ad0395
bunny-warp-contrary frame_0000.exr 4224d8c0ac93043c1737387001260dd9eb258b19e5191507addc630f44ab2717
bunny-warp-contrary frame_0000.png 3d534c7303cee1d62c189ebbbe9980267cfd73fa75d286a6d2806bc0a6988668
bunny-warp-contrary frame_0001.exr d1309883c514804a9c824f0c81522cac5db2738de5b9cd82f2e3dfca2a19be86
bunny-warp-contrary frame_0001.png 0865e12bacd879eb97486058cf6fdb9fb95562c8402d37a4bf668d8072bd4efb
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv 6a80d3d5122f34b66f6d1c0a198f92c5d4d97e296a99ec8d2a70bb147d51406b
bunny-tuned frame_0001.exr 62b646ef6fa5f66c411b933afd2230cf2d22ff5dc8764fa0aaa44e8c7eefb459
bunny-tuned frame_0001.png 0d480f37e987360b28100241281c889ec9c5a4669e3469d9a1ab144e79992d9d
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv 2722223dd2135845d95cc8878a62403f7f49961127b19f511b00e56a0cb0792f
bunny-scan-block frame_0001.exr 3c7b72e39453893c76bcfeca18a44a42a70e673efb7aad3c9447dfb2c78a30f4
bunny-scan-block frame_0001.png 37cdbc3a047cf2e2ff395d52ac42927b0a1795b97b509012b74eb2f16d12cff4
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv 894fdcd38d971118b4fc635b79a56626e20f72f00a72d065dee8f05017b2d58b
bunny-validate frame_0000.exr 26ba7d72ba6a8cb9807a9e1695a18210fac779d6852b09c32cf545c85166a6c7
bunny-validate frame_0000.png 236063a9ee443ee22933ca2cedd81e695d8cf76bbc2c270cae4903ce302d1471
bunny-validate frame_0001.exr c61da508a456f9a8a92f7ca096c30dc65e86ee7035b67ada555ea02cc2e1b6ab
bunny-validate frame_0001.png 4e72fac213350e434fb0981c87730b69711a92a8ee9a42e9ef3a578d234a99e5
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv d56dbeef5ebfed153d13084e89a742434710e04c91591eb3b40f9c821db8a977
bunny-validate-warp frame_0001.exr 0f893b3e43ff3957de0143f655df796c01209736412f9926cb9c7bb415e24fc3
bunny-validate-warp frame_0001.png 05801fa340bc149cd976c822dcad632785477d2aa6c52cbe73b3ef674e7c136d
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 9dfed9e848ce035b959945646056982a221c6cd8c212d0303041494c6aad2192
bunny-validate-scan frame_0001.exr 92a30073dbf83b5beba97c5eebd1605effb85752e1c9c0d4864cbcbc508d47e0
bunny-validate-scan frame_0001.png 1942ed96049382c3f52aecf38bed9f2f73faeaef5218d0a67bda23695e7c0335
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv 6ba8546b3a42d09e381fd16cf10d6aacbb91ac301adbed562f11fa7ed73c2a88
bunny-temporal-orbit frame_0002.exr 574a8020a66111bef48271f3cc1f29ed52810ce1bb21d7736962d6ba8a981381
bunny-temporal-orbit frame_0002.png 5254d28d5279eb54eb2551251e71c68aadb4ce1faf80e5649e33ead5b510ca34
bunny-temporal-orbit frame_0003.exr bec31e381f8456c5eaef20a10c1e60b585ef3f133f58f984d4e99ed58469ac98
bunny-temporal-orbit frame_0003.png ce63446e3242258ac29c517f137e38063b1b6f5edf27bed5fccd15eb41af438b
bunny-temporal-orbit frame_0004.exr 82864c5fc6e976d595abd20b0342c371a44ca495d64317fa60ce9cd5e69117c0
bunny-temporal-orbit frame_0004.png c658e247c793b06f13843ed43b036a2c0af223c9f617b55217ccb998fb0734b6
bunny-temporal-orbit frame_0005.exr 75bca589e23aeca72bd40185fe1721d0e0b71bc3edc24ce89008d0940237c359
bunny-temporal-orbit frame_0005.png a0599c4a90b878b08be000ca70281797e1c9513421aac59efad0b426c4c17a13
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv 127185c9e158e66c7cb75e0c9bf7257afefcaf13fedb727ebdd9ed9fceee5adb
bunny-temporal-warp frame_0000.exr 53c404706c6deed48d7fa7a88a52b4afa9c03d47c42a089637cf9d3a754c3224
bunny-temporal-warp frame_0000.png 1246f2d9bd711e064c78b288f24f703289019d500b561ebf2fe9e08631db0c13
bunny-temporal-warp frame_0001.exr 3683839954c8fe2a6635ea8d32ab0c517cc3331ef659486168eaf0ff4253aa08
bunny-temporal-warp frame_0001.png 17400d0f5d7df8cc33ccfd90f993fc04ab8f36e5ffc843e790adb95dff399fd3
bunny-temporal-warp frame_0002.exr 397eafc79fcdeb9d6cefdbad07105be88db2a97fbf4b6c5f860925952baa957a
bunny-temporal-warp frame_0002.png 7d76f854bc033b0018e161547d1e6caa5d75e517c27d6760619cf1420b5a158c
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 5ec83275df1b4d20ac5e883b5d27caf1c1b80db1cb4ef9b89c5f41b980fd39a0
bunny-temporal-spin frame_0000.exr ffb8624db0e6009835d9af1698c3709f58833bd52d3ec85f56ed0d37ec05d94b
bunny-temporal-spin frame_0000.png 0d3ad9e70bb40d9a777911e8d48aec97bc41175eea87f306c962dc4d303814f5
bunny-temporal-spin frame_0001.exr a7872c863916172f17362043a45f6b06dfed521cb2b2c8129dcd5ade86b60a22
bunny-temporal-spin frame_0001.png de438a548f0e32a20e08dbfa5c19ef9396906c21b90d768c377e3a725cd40960
bunny-temporal-spin frame_0002.exr ead38abbb0a673e0c245c8d7482f3a06fe96b53eaf1baa7090a8ced1df5b820b
bunny-temporal-spin frame_0002.png 016a9a1c635ecc04323e4feed7a6a2ccc523af595b5c90204e1d9fea72ce6726
bunny-temporal-spin frame_0003.exr 7abdbc5de6c3cb8c27e24f43afc9558d87b49637605679f8dfb831fcf513a35c
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
