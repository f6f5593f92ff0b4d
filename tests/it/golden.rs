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
shapes-turntable frame_0000.exr 64ce02a5df4cda0489b94ff966af0558ba464d99735944a7dd2bf1e776fa92d2
shapes-turntable frame_0000.png 229848133558b63e882681db556fa934ee6c92884d05a0dc8ad5997c78b0efc5
shapes-turntable frame_0001.exr 0a995e0ed3133192193af92b2ff79af55955b6c958fff11830df26ddbc9a81d7
shapes-turntable frame_0001.png da5127720b0363fd79c4f28ba14444c1e0db52e91d6931921cca55e0655c3255
shapes-turntable frame_0002.exr 6176da842db9d950839a0b2810b8923bbd793aaeaee1c3afedca7daa4ca3d058
shapes-turntable frame_0002.png 317219db1d992a09f1dea56352c5c851972617beac4c060eb983e969fc9764de
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 64cdce06735e4f8de3eb4182644b8b0692be078d5142ed7ed530e1ea3b114b5b
shapes-turntable-spp4 frame_0000.exr f1712e744f7160fd6ad354cd259699319231cca7190bfa073c8c66e2010c18e4
shapes-turntable-spp4 frame_0000.png 231ffa6f76bf1bd20b6cd5206223a4f0f94254996b2a2f55f5fedd88c4932ecf
shapes-turntable-spp4 frame_0001.exr 6f7db0cbec7dbd7f4c39855e6d664e2f39a6819597265d7318bd9805c27f08a2
shapes-turntable-spp4 frame_0001.png a6b859039d3af965a241082932bd679b9aa7105ede955e55783ab40dbe96678d
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv 38335bc14c9e77bed80bbb87d1fc469cfef18d8cb5e5d824bc471243b7a69427
bunny-none frame_0000.exr 856966d53f5001805df8a0d24d064b602a3224aa78e8e30b836de9b786bde17e
bunny-none frame_0000.png 1f186438920637cc04e8892c5e6e859f8fbc6df972cf9dadc4390e62f80ba15d
bunny-none frame_0001.exr 2e928b7b4e13754d6e0b2486423f27c33307c12c884cc1162cf48cb879b4a511
bunny-none frame_0001.png 69f443aabd4e54afb3bc78acdd1afde2dac40ec15950bafddc830e5977822dc8
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv efda23c1182142da2f39b8ed0133b471838c22b92a05684d9195c5fbf6d4004d
bunny-brute frame_0000.exr 414c820a09d6ec58c566719de2188323295bb44699927cf3ab807f1df2c90dc6
bunny-brute frame_0000.png 31f3dd0542641f5862644a852da467e09e19a9608e78790fd4712dab244afdac
bunny-brute frame_0001.exr b7650685860d58a53c239f1a4ae1d62df64b76d277b9dee26fe2b98dc4fc3b2e
bunny-brute frame_0001.png 72bd048fd618103eaba39ee4b99fae8a11fd393c0c2c9b70476c7c8d8d00543c
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv 11670b6e4e47509bb7731a982257716f0c3d38f2ea99cf6916f7a36cc640fa8d
bunny-scan-warp-boundary frame_0000.exr 7f1a87d854dff5ce831ddc8595833d29d449b589b573c6597f081f4243cec098
bunny-scan-warp-boundary frame_0000.png 4f8e20d0cbc05c923f7c9ec34927ae16edba5150ca199c41f53019d8a1636be4
bunny-scan-warp-boundary frame_0001.exr 2d755c5aa1a2ac3210a3eb2a448983780da9ea31088003bce2ceea2f302302e8
bunny-scan-warp-boundary frame_0001.png 45d39ba673b8a7c346f5018987c2c3e1686140bacbc5f8aee9dbb854e4c0c9cc
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 4540f78e67772942d4239974aa1e98c9bfb86388d932d5f6c6e7ccbeb22d3347
bunny-grid-warp-boundary frame_0000.exr bacd120f54926d80e85dd9ac61f5797fe6b97cc7128611be36ea36d083b56cdc
bunny-grid-warp-boundary frame_0000.png be9920c2865868234cad466646757e07880c8d2519cb94aad5442f011c6a5247
bunny-grid-warp-boundary frame_0001.exr 0cc2eaa51073cf6e81b600e63fb9c38e5ce3d60c13f74ffb8024916ca7df579a
bunny-grid-warp-boundary frame_0001.png 45d75c6ad021c5b53dc6b38df72824bf942ee51e0aceaa32b70b93e31d786ef8
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv 72881fb9b136ef298afd514c463a83e49fcbd4f67c642ecaed0da636a2a25567
bunny-grid-nowarp-boundary frame_0000.exr 085acf4aaa107225f128cee8cb2d82d8da604087f71c6f03a2591c4d8fa4d4ab
bunny-grid-nowarp-boundary frame_0000.png d96a9f804db7583b25cd17510327a02b4f7241a9ea769c0087bf8ade5decbc39
bunny-grid-nowarp-boundary frame_0001.exr a5fa01b00330582db6f9549ca0893518017d7f15c9f611677b56a8d1853b9466
bunny-grid-nowarp-boundary frame_0001.png 3c1da2de4d278619a365c81586aaae0371dec88b4bcf43968771ac0da6a13adf
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 24afd8e5b9d73f7c1d9dc57b4e07460873cb29f38f53bf4f098929a4258a1427
bunny-grid-warp-uncertainty frame_0000.exr 18f0f9744849c9634ac146a0dbe6a9a44f1ceeb0025b045847358a8cd3d71c95
bunny-grid-warp-uncertainty frame_0000.png e55e9890554063dec9086b6fccf42d836c4eabd67c060f600c2c77f6206805a2
bunny-grid-warp-uncertainty frame_0001.exr eedc90e5f743cf7c3d4ff75a0009341f55ef6abd8fe8b55c60f2a760a1758735
bunny-grid-warp-uncertainty frame_0001.png 13b4116673a82813c4c19fd4f83a7f50aacb8c6789670c2b44b4633c1990c743
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv 4d9c29d8e3d29cd85f9d53c5c0ff0705ec633ba0174ac97740c2ce1d60e8a220
bunny-grid-nowarp-uncertainty frame_0000.exr 44e3eb05b1d239fa9d97af9491dffce6de4b1532212f6ab91d8824942fdae414
bunny-grid-nowarp-uncertainty frame_0000.png 2c6981205b9b800669be94fd4ad2b90255c19a12fa49525658468e9118332b0a
bunny-grid-nowarp-uncertainty frame_0001.exr 58462ddab2a705bfa3157c0df7b58c794bc5016a9a62f2af483a4e873f315ac1
bunny-grid-nowarp-uncertainty frame_0001.png ba7c84e3833e2121221ad867db577674db5b3108b2c878135ab8a89a58c5e3b0
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv c30136179f603a18c9afbfe6c4191703a7c23805b6a65a11becb75532462b4e1
bunny-scan-nowarp-uncertainty frame_0000.exr ba1a1dcf3092ae515d6c6b9288d121f5eab0e6fda725ba0622f7088e62112ae8
bunny-scan-nowarp-uncertainty frame_0000.png 7a1a50bf5c3058ef2e9ede845fabcae4ba23b08f2dcd115b76fd10d34de174b2
bunny-scan-nowarp-uncertainty frame_0001.exr fea21b695c61559ed760f92dbf54eea7723005afa1cb5fca7faaaa7db59d8cb3
bunny-scan-nowarp-uncertainty frame_0001.png 1f05caecb69b85d960f9d625f63e63d343bcc0dd193158ae9148d782cb6df09d
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv 1fb50f1595ea5589b6da60374c0b72c027ac55f14761cb8ea4857cf727faa0a2
bunny-nowarp-all frame_0000.exr 10603c7111d28360cb1dd78ed09f10cfd5e5d9846a5be285c0cc3a3d8f3bd9a8
bunny-nowarp-all frame_0000.png 6a8c791fc9fd1f1a8fa88b8ac0f1d49bac9c22b6827aae5781b4067d2d54e1c0
bunny-nowarp-all frame_0001.exr c76b6e3582ff943b883d381c9a465e22647b8248e64c013bd069991d64439cc0
bunny-nowarp-all frame_0001.png 01352ffadc297ccbbab4f0532f034d82c369fbf352b213df03f5b0fd46bb6cfd
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv 63fe581ce0437b1433d8aa1d80eac76dc2b3b5fd8b01d06f06a96e53fad5182d
bunny-nowarp-contrary frame_0000.exr 2cc12081e114c7b7e03e3dc628758dd4d11f0ed8cbec482ea4eb38246a295236
bunny-nowarp-contrary frame_0000.png e5bb56add9677c59cd5fbe306c58341de7277355d3b2b4e5780e0e8b4170fdcd
bunny-nowarp-contrary frame_0001.exr 77f6b0a7202cdacf17fa73dec2818dc40708bb3bb34e4b9995c08d49390e3de8
bunny-nowarp-contrary frame_0001.png e1ffb66213b598d324e098e70ca110706847bc2a449c4e9628dc486b45ebefb2
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv a9ef5bfae8ff18bc577b49726cf4d0574bca55f9afb75879dd6b805d1bf0125d
bunny-warp-contrary frame_0000.exr 95a69d2280042a44f60f0abcb8d5c2992e064cd210010b6262f8805bd3f3c74a
bunny-warp-contrary frame_0000.png d69aa2f59247b092ef2f13c0968992184be4b8d2d17d0b7f51b67889d81b18b9
bunny-warp-contrary frame_0001.exr 656a2dbaa8403153d1768c03aff4719145e8b4f3ac4e0cef23a08625c6c77fd3
bunny-warp-contrary frame_0001.png d8d961c129ab31189f26d061a4a19af183e009a74d5fc34a35daa337628d36aa
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv 346b2e0c186570d4c8f1cf85a041788e4cce8dccbd150162a436b9760462c1af
bunny-tuned frame_0001.exr 7f11f06b6d267f86af152eb6e93c71f8aa01f2a6976ca4887443c7fbcc31e45c
bunny-tuned frame_0001.png 1966ae2e1423a5b0ab234fc3ea95c737828d1a3716661fd85ca2fdec000bea8b
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv e81a01c25bda4d1f24b515a9d7c928de756b88845fdf3c45d4e76993ba4b310b
bunny-scan-block frame_0001.exr 4d325f8fcf20f7362bfe1984d8413cf030fc58b7b82ab846bf6b9468ab1573af
bunny-scan-block frame_0001.png 79506ce25f7850d596a854f5c49ebeefc0c7d596e868e26b62844627e94be4a9
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv bfac3e6f02813188c99682610f8ded5449c6cccf91d46c5e859fa2b751321c7d
bunny-validate frame_0000.exr eeb834addaf5b97458e86c3f23b9af05af31b554e766bcb179a6b46f5636c781
bunny-validate frame_0000.png 2c6981205b9b800669be94fd4ad2b90255c19a12fa49525658468e9118332b0a
bunny-validate frame_0001.exr 0a3d8a8dcadef358e77009c3751ba8a15df22c749ca5c3c79c0496dfd7591a4c
bunny-validate frame_0001.png ba7c84e3833e2121221ad867db577674db5b3108b2c878135ab8a89a58c5e3b0
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv ad1abd864b78f5f9b936613ad4fb4928bd55c42545e866e7d8cd5e785d5414e5
bunny-validate-warp frame_0001.exr 58cd2f2ad183dbead4dc67dbc002aa08c92fc7d0006b333c60e7c83386c95307
bunny-validate-warp frame_0001.png 45d75c6ad021c5b53dc6b38df72824bf942ee51e0aceaa32b70b93e31d786ef8
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 73e0c3f61c669545da565a310e4cf6912473c04688a9b45aa8d7b728cc8f3411
bunny-validate-scan frame_0001.exr c8cd507d5aa44bdca5c21ba4e49f817072d5f0f5311ac030cf9aed60e80ad043
bunny-validate-scan frame_0001.png 45d39ba673b8a7c346f5018987c2c3e1686140bacbc5f8aee9dbb854e4c0c9cc
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv 947deb19aaafd5998a34e3945727b8fd6399fc59fd331624e7532dfbcfacbe9b
bunny-temporal-orbit frame_0002.exr 8f3342927b6908533d982dcffe5e86756cc9f6e8992e6fca51e941509b048131
bunny-temporal-orbit frame_0002.png d94cedb866924ee77c8a8a8e4192347d7cc842077779e22a810e629639f0187e
bunny-temporal-orbit frame_0003.exr 244bafd13472b2646ea5af88417a707f29076aefd029ca28d73d45c9bd378b68
bunny-temporal-orbit frame_0003.png dc90a7560985cff7e723aa0957195e8d242cb97e17219df395696724513e75fd
bunny-temporal-orbit frame_0004.exr 483301aae85a31e4ff40f1016573be4b4a903c2af49f8112aac6b3dd4dd708cc
bunny-temporal-orbit frame_0004.png 3ab245ebde92e683d6ea3526d763902f5a8b2bfcf6318d5d7ea31d2f8e9c7b9b
bunny-temporal-orbit frame_0005.exr 1a7fe8e013ea67e42de09b83bfdf14563c8cf4e905b838aa06a8f32b234731ee
bunny-temporal-orbit frame_0005.png fccfee36e78d737190ac619ef5cae509b70f9b13842419bb230bfef7d65b0d4e
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv 10c6edac144c88afa03170ac3fad0c82d96599c0d9e66c38da35f8d3ba7fca59
bunny-temporal-warp frame_0000.exr eaf1b374c3ca8181c027b4b31038a909bb338fca54ddfb03ecac5e5d7f04f7ca
bunny-temporal-warp frame_0000.png e55e9890554063dec9086b6fccf42d836c4eabd67c060f600c2c77f6206805a2
bunny-temporal-warp frame_0001.exr 65f2b4fbc96758a5466b6499dc909edf3ee951f423a5ded2dea0c52be8a7ec49
bunny-temporal-warp frame_0001.png d1edde4a94b5dd47b52293a0d094780ea6b96cb04e6fd697d25bebd91cf8bce7
bunny-temporal-warp frame_0002.exr edfd0c2266fa70db68cb39bcd091b90c5f9095caf26ed56afd33cc51ea2debf3
bunny-temporal-warp frame_0002.png bfc2db9c052ba252d5970288c1addd721eb5040c37dc1fd2ac4783c6a8078a20
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 6bac782d1c92978eb6292c01bd35fd5ecd56d7f9906b9007f30385005490e8ad
bunny-brute-lambert frame_0000.exr 4c228797c448a48345439cedfb7947395f9d4b5210a32a52927bc68a871c01bb
bunny-brute-lambert frame_0000.png eae4b153d28edd0222e0be92b54f67f9b420ad45f46038c7dd0b278eb574d070
bunny-brute-lambert frame_0001.exr f0f7a4de74fd55499b68cea3de3856326ae2e4dca6e8b83a7c3ca4df90dc31e3
bunny-brute-lambert frame_0001.png 2cc5591ced6d8caf209da42529ffc7969011e2fa2a1ed53be7f50d956e85a8be
bunny-brute-lambert lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute-lambert stats.csv 11670b6e4e47509bb7731a982257716f0c3d38f2ea99cf6916f7a36cc640fa8d
bunny-temporal-spin frame_0000.exr f3fcddcfa6c6f8dd316d8fe8da4938420d674a501a9155cd135ee80dbeb2a1cb
bunny-temporal-spin frame_0000.png 1f776eac925f737af5ef09a062f70f1f388265a596dd434c1c0d0134aa604e61
bunny-temporal-spin frame_0001.exr 01d410ee9ac694ed40b979493f74b1cdb8b3f07b2b413ebeab834854671d80e2
bunny-temporal-spin frame_0001.png d256c663d35acc2362c27ea263f04764607388615cb6a77eb7b0d5303f182136
bunny-temporal-spin frame_0002.exr a81edde2b876017c07464bbc3cbbdb32ee98c7d5ccfc554f6ff478ca87cbf472
bunny-temporal-spin frame_0002.png c5f80106a6332aeda4b23f0db3cf34a7573569aaf1f8675f1f9910011f42f355
bunny-temporal-spin frame_0003.exr 65f9ab238706214728912e810057657e16c5e1cfbe4105f60d58f4dfef00b4c8
bunny-temporal-spin frame_0003.png 231c205a6bfaa8700e321bf2bf9f83d6de4e11be1fe3633b0868eaddced7ba19
bunny-temporal-spin lights.json 103f720aa426b7ad9ed05f0b47b0a7d9096a5429b996d950aa4e62c981aa7cd5
bunny-temporal-spin stats.csv 07d70e558869e8722d14a922a8e624f1f13d07b2016034444ace18bbc32d4fc1
bunny-spp4-pixel frame_0000.exr be1350545a31d0a9e88ae48370893b11f3ad96b27526f28c7fcbc0d46ef919a8
bunny-spp4-pixel frame_0000.png dfb3532fc8664834d2f3056341fd7874e26faea3e9a046cf4118104833e972cb
bunny-spp4-pixel frame_0001.exr 4351a5685e838289f07384613305c2b7d76eb7a72148ae4cf94e3c91e9420a64
bunny-spp4-pixel frame_0001.png 38a723887037c23712c8fa63c7224f4faef7e7454ba5c83b4e1aa1ba1865142b
bunny-spp4-pixel lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-spp4-pixel stats.csv c69315cf658d3e956284809022ffad1c7b55afb404728581cd39dd7967c51d0f
shapes-turntable-spp4-pixel frame_0000.exr b01f2d7baeda21acc4ff9e4d9e8c7c98cd0a383ea190304bc9d86391ed526a4f
shapes-turntable-spp4-pixel frame_0000.png 231ffa6f76bf1bd20b6cd5206223a4f0f94254996b2a2f55f5fedd88c4932ecf
shapes-turntable-spp4-pixel frame_0001.exr 7446e876f1a04ae034c1fd90a2b9bc13bf31e00f0e22fbe6fe8d02a901a3d4a0
shapes-turntable-spp4-pixel frame_0001.png a6b859039d3af965a241082932bd679b9aa7105ede955e55783ab40dbe96678d
shapes-turntable-spp4-pixel lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4-pixel stats.csv 38335bc14c9e77bed80bbb87d1fc469cfef18d8cb5e5d824bc471243b7a69427
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
