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
shapes-turntable frame_0000.exr 977665ef3842ad51d6f40f4acf9d4fcb437f430d100937bd758d36ea9cf96d53
shapes-turntable frame_0000.png e4b08ebe637f0d59a59703746b74418db6bb4577457b789cc54836738a644610
shapes-turntable frame_0001.exr f142dbb317eddf16b44ad34f65873d134378f595c1be5875af014153b1b2a706
shapes-turntable frame_0001.png a00800bf79d2dbeffa5e8f9914f4dccd35922ab7d9c0bf487ffc92646d5ed552
shapes-turntable frame_0002.exr ed6136fe8134f965809d986c3a2ba426675e77a18d66379dae33877be15519e3
shapes-turntable frame_0002.png e962bf93cbfc39be000d61098bbe8e5c4f53131109af13dbea4dc4bac063cb89
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv cfb72e51aa5dc920e25ba831476261c594af220791081bb60e38f15da0ba8618
shapes-turntable-spp4 frame_0000.exr 5194f56e802e3a1e95b400c8686eab0a9b4c2fd02718c6f8040e711000881ec3
shapes-turntable-spp4 frame_0000.png 1017601ad2a5b4935d5441e4eb7909e9625a9f07e05e1cbfe0350148358983be
shapes-turntable-spp4 frame_0001.exr d1e570d073972c7923a30c52dd7c9a4c35f4d1bdfe7b9da2607b7266f12889ca
shapes-turntable-spp4 frame_0001.png c4e3713fbb534c9a52077c215c7fcb3b3bf950e73f6461dcea0fa96869bc18a9
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv cdda06708f070c9a6cbc11bc9c22794792589108c7d547e6b5cb0138cec55fc4
bunny-none frame_0000.exr deb8d8109c00109ca28626dfb773d4d4c8b7c9511bef16f34775561d19fdd98d
bunny-none frame_0000.png d3815e9f495cede07147b61fdbf7575abaa2b1382493c087c0902ab58077d257
bunny-none frame_0001.exr 70e82878a51ebd78622673168ec37f0fc5b91a8695e1bc9dc304e64fb8b4c2e8
bunny-none frame_0001.png e134beec67346727900077c73e7ae89858a8b22d72d4859653eecb71f107011b
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv f81d6fe21e7305425deef527fa8b936ee80aa86cbb74e321678e5bc73fda57e5
bunny-brute frame_0000.exr 31efbe6c1388fe6fcc72412da7e8ab9fe45248dde3cf3bc37482c2640258574d
bunny-brute frame_0000.png 33c4e3d9e43014dd518cbce458518d20fc032cf028c1c3ccd2b342a825a73e98
bunny-brute frame_0001.exr 5b3ada5d5c8c5d7d0bb02b98e18fe04e21706f2e032174f4060fb2be56e6b2d4
bunny-brute frame_0001.png 6e2544bc07bd7bb298be032cc7a3dcddbdb648c8e8d156da92296af020ecc79a
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv ecbe98428374ccf54efba77e17cae9f777d3bd21f98341a50f148580a3e62e5a
bunny-scan-warp-boundary frame_0000.exr d1638bb0aa4a92ea7816ae18a7693b03141e25214ce332249efd25048451f588
bunny-scan-warp-boundary frame_0000.png afac7c0e662f09e397ce9071913c1461dc34b451433ea125112e424a629a85de
bunny-scan-warp-boundary frame_0001.exr 4022113bf76f1836929e76dcc1980f06e03d9c5eb45ac0fc501ca5e6d70baca5
bunny-scan-warp-boundary frame_0001.png 7253a442e8e7aba716190a7125c16f914cdcde3a1627e614cf29b9453167b9ce
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 4cd9cc6b13f2ded9634b79d422f02501a8b582a09860a6b3370cf40be86ceeba
bunny-grid-warp-boundary frame_0000.exr 2cc008cdef345df5f29ff17c9a0910e927e95cddac6625581b25868dfba6ddea
bunny-grid-warp-boundary frame_0000.png e1b9c0244c3ab05a417f08fb03cbf2dbebee227da9c29a7b97c85b1de785d3f1
bunny-grid-warp-boundary frame_0001.exr 1dd9cd3e0cef68ce42ee5e299e8ed1bfdf04336327cc1c7dd7fa3fe1e1b2ba61
bunny-grid-warp-boundary frame_0001.png 7e57a9761e0ce5853a0d52b4366a93e5134c0b6681407d71d68122212edc8322
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv 97e04c6866e8dd8694211fbb8d2e9b720d24584ccfe5d4377d4e366681b12468
bunny-grid-nowarp-boundary frame_0000.exr 6a14396c93ff44d9ac74e24748e6a1473444efc5e205cf85f2218e39e274c9ee
bunny-grid-nowarp-boundary frame_0000.png 3facdf68bc11696b60b3a2943853814ef5f5656da773210bf376251d7e1942c6
bunny-grid-nowarp-boundary frame_0001.exr b07822bc963780a17939e16fbea1992164f44577ec2fb70ced9cef3c434cb413
bunny-grid-nowarp-boundary frame_0001.png a2b824cc4e67ee958179170f977dd504d91eb86b377e30b65835d53c6a8832e9
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 612ebc90dc614681249b37f39420459e276755192b94e9f0e0b37f7b484ce1f4
bunny-grid-warp-uncertainty frame_0000.exr 2fb01bec9e85ad1cfdd240f35a54b9145b2dd7488b8a5045202190b96d1a87c8
bunny-grid-warp-uncertainty frame_0000.png d93d62203a4ab609a3242b780112d5409845a689c389078a20791461110011f7
bunny-grid-warp-uncertainty frame_0001.exr 4032de9b7b02ac05a987bd8ecb3f9b9ec6c4f018962d1b587c503c0ffa55e755
bunny-grid-warp-uncertainty frame_0001.png af1ac83735ed932e210c849c1f818d638631e4940fcae23f634433e8ae4ca8ab
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv b3072e97c77a8e187c931863497b2d2d96722bfc0dcc91f083cd7cbdace30dbe
bunny-grid-nowarp-uncertainty frame_0000.exr c13820bf56a8bbe82d8dd2725dc7f61260b320dc972fdf03883c8dd56092645d
bunny-grid-nowarp-uncertainty frame_0000.png 5e2b5c54fa5f640e6c5a2d3737df07038b02ec29d78f2ba97c14e8737a4dc654
bunny-grid-nowarp-uncertainty frame_0001.exr fa7b528561edaa0cd4b759150b68b4cce9132bbf8cba7ac6f1ec942e642ef1b4
bunny-grid-nowarp-uncertainty frame_0001.png 0330e00a8b27daef96564e4a214d5e604dec6f371d384b1775eba62983ddf791
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv 62d142e5247facb199cf68337807c7344e6da36fc963e45ea3e037011bb9cf80
bunny-scan-nowarp-uncertainty frame_0000.exr d56a6630bcfd1e78315bfe8f1f0ce56ad37b08b994d0ca639b6f5837a37dddb2
bunny-scan-nowarp-uncertainty frame_0000.png ec8699f91497bb9f243b0d83e0bc5514d77313e6410c6a21806342e536bbf917
bunny-scan-nowarp-uncertainty frame_0001.exr 4c2c3197428c3ee0f7f62a5f55ab85cc660f9f1c08fe2d439f1edcee5cee1de4
bunny-scan-nowarp-uncertainty frame_0001.png f835f82c206f55d117b403176727e2271885f349fb674a15a2e42d97f125efe7
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv cf049c0cb34e36b29f5f73eb3629dab525daa909e1128871bd1a9f81a7f76c0e
bunny-nowarp-all frame_0000.exr b809e4f6fa7bf9f30f1798fafa156473a2d97208fbe59e8835d5ceb477c5f423
bunny-nowarp-all frame_0000.png aaf6ec70f6e4104a73b7f9e0ae434bf5c1d0d1813cd561befc1a8b5777b2c542
bunny-nowarp-all frame_0001.exr 09e5d3b7554dd7b23211af3330c8d6049ea475eb8a72436b807fa448b11216af
bunny-nowarp-all frame_0001.png e7f489c182aedf4b0df926592b099e968954fbdcf6854ac790b95bda863406b5
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv 53302055aff94d70327af3d8002f6db85a919d3a3c5044a45ba8ac58e25c2399
bunny-nowarp-contrary frame_0000.exr 4b1c77e2d8ab1f110dadaa05353041912b4dd23118a9ed0d11ef7635bc4fd959
bunny-nowarp-contrary frame_0000.png a0edd0486f7084230af44447c4028761c9c8761512d12beeab397a63debeaec3
bunny-nowarp-contrary frame_0001.exr 3746aea503ea53669385652ddec182c1fa7d40c47504dda17c6d9e821019bdf9
bunny-nowarp-contrary frame_0001.png b7cd32a82af651291aab13b4e5b35b35812576df96e3afa79d8490c6fd4cd24c
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv 9d1f9a3d64d580b35167fb78678eeedba6924d0c71d2edf88db88551d9cbdf96
bunny-warp-contrary frame_0000.exr 611b8e408897f9f98504c483dfe01a871b9c5267accf41458223b55ab9f61978
bunny-warp-contrary frame_0000.png 838746a03ed215211e0e519200c39437dfd67899a862b03e46453948fd3ecd4a
bunny-warp-contrary frame_0001.exr be81a7cce927cc979fadc87442edd8736cf54d0a4da8d7fff9709adae301f010
bunny-warp-contrary frame_0001.png c20723c78d21fd14c087ee3bbae70e8bc5691524b5a881d7610c41235b223b24
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv ce16a35d5ffc1da5e5f1b094261a2996492521ec3c80c2ac1d4fa42982973db6
bunny-tuned frame_0001.exr 872b110c46b658809fcc345fd82c3a1fe1088b4586a9395ea411caeafc927d41
bunny-tuned frame_0001.png df0b9b738107a1130349e7aab1f73c0a7999fbd6b738221802cb12843e268b06
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv ea224d464856547cc701b51cf5e6e9fcb9b2ada54e8068ff80e0463e9ff4a7d4
bunny-scan-block frame_0001.exr 3d366e804fec6f9d1f34c66a66fef947cd04a36a0abcce7ebb89236ecda37ca9
bunny-scan-block frame_0001.png e1f6257c1496a3abde30b9d903f52d78f6f2776e9230e901fa1f6cc9f8ed26c5
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv 8c89adc2c0019838b4961c03e5dfddf62940fa4d7ba8066a821f98134319170f
bunny-validate frame_0000.exr efc2626e6313d20ea7b14b65909f0d83d12cfb3b14a1e1df5197027a17b98e1f
bunny-validate frame_0000.png 5e2b5c54fa5f640e6c5a2d3737df07038b02ec29d78f2ba97c14e8737a4dc654
bunny-validate frame_0001.exr 7f3b662f69303e93fd8cb99e9f405a278da8cfb80ea6195d697465199e6ff744
bunny-validate frame_0001.png 0330e00a8b27daef96564e4a214d5e604dec6f371d384b1775eba62983ddf791
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv 187320c2212a4591938b69f9c1b0dc4b87c79d1263a8a303a9e379716aa0caeb
bunny-validate-warp frame_0001.exr f5e0b91937b0d88d20f86d17e432dd6a74565c898caf1e6b28fa58662b4e38af
bunny-validate-warp frame_0001.png 7e57a9761e0ce5853a0d52b4366a93e5134c0b6681407d71d68122212edc8322
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 6563b306ec80f59d4893579dd6b688e7e2e2bf003a5d22b7446b96e56f951896
bunny-validate-scan frame_0001.exr c1ed8e796542f34f94918c1e7fe790454fce677bad17033d23468f476bcf59ec
bunny-validate-scan frame_0001.png 7253a442e8e7aba716190a7125c16f914cdcde3a1627e614cf29b9453167b9ce
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv 254bf40dc66ff05a1350f4034cccabfe6009693ffae2bfd1bd37c19422b83626
bunny-temporal-orbit frame_0002.exr 75579a95f550735ea357b304461ee675bd8864dafae68eb9e5049ac133272150
bunny-temporal-orbit frame_0002.png f6cc2397c1e459c6404a8007fd4f6ac5c353ab44f36800079f67061f07c50aca
bunny-temporal-orbit frame_0003.exr 56e3b640526f4c7433eb8dd0be80ea61c61f981915870d813a08dde635a92c44
bunny-temporal-orbit frame_0003.png 27abb72f0349cdd59c2ca0b954bf1f0b63c94896fe812c1bb9264010249a6c61
bunny-temporal-orbit frame_0004.exr 72f6c4f95ca1932e06b9f3107018507401d5e25b1b70ac745b631aaf1af45866
bunny-temporal-orbit frame_0004.png b89cfacf208d40a00e5cc144688a66f62ad3e53b6ebdbfe7be353ea418cface7
bunny-temporal-orbit frame_0005.exr f40a6aad2c8757364c9d949f6ae5295bc3b647cbc7a7b88278477ab33183109c
bunny-temporal-orbit frame_0005.png a3d6d8e36bd970f70c8a52bc91c99ecb4b975ac5eca8596b6513295073875642
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv b875465741d9e261d4a94a75e6208d4978301be90fe8bb9e7bbad919adba79aa
bunny-temporal-warp frame_0000.exr e1733cf8f738fd3bec3797e7c5bcbcd5115bc2cf1599f313d969a6049babaa32
bunny-temporal-warp frame_0000.png d93d62203a4ab609a3242b780112d5409845a689c389078a20791461110011f7
bunny-temporal-warp frame_0001.exr 548a7ec23318b47f74dff36aa722db3bd3bf819244a27665664b19e894ba9def
bunny-temporal-warp frame_0001.png 85dfa005293dff55954852ada7a5e82d56f0cf572a76ccc46c2a03f26265ae23
bunny-temporal-warp frame_0002.exr 8b8691a7c6e20278de4262376dc8f003d7cdcb5470c5a97cd25b5e7f48890ab8
bunny-temporal-warp frame_0002.png a1db397cbdac08290eef4f702d6025c9d0061c5e6542cd239893b27218912265
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 00a9a6ad46823a6465c639da53801421ed001d1bb66915ec800db479a05ff7c5
bunny-temporal-spin frame_0000.exr 4ee53d094e3001c65c3eb1dde96a0f1564651eec5ee66cfc0de9f7b83e0c46b2
bunny-temporal-spin frame_0000.png f69714d86ec9edf58a230505c98050a140f3e58ad472f0d5bc6ca4ec2e49025d
bunny-temporal-spin frame_0001.exr 1a514199209868e9f18b4fae54835cb0e38193c49cc717d112f43da9f13144e2
bunny-temporal-spin frame_0001.png 778f28c7f02cd27df7e7fb6166fb76dd29f798677e8321930ceb50015cea485d
bunny-temporal-spin frame_0002.exr e9aade85f5f25d6cc2620f541d4a305f7090835e8be8040c477c6d0576ace389
bunny-temporal-spin frame_0002.png c7ef042bdf067922204001106c40789bfcaab1e384bdfec4861bc3b96f52d650
bunny-temporal-spin frame_0003.exr 618db85bb8a0f1c5946353fa85e00412c30ab3e3e2fd3ef49c625655764e3a79
bunny-temporal-spin frame_0003.png 270f29cdc43073c293d18b6aee29843c6240e4fa311aae54e23a399713ba3d89
bunny-temporal-spin lights.json 103f720aa426b7ad9ed05f0b47b0a7d9096a5429b996d950aa4e62c981aa7cd5
bunny-temporal-spin stats.csv 3293c2cc3d2e5760b6a7d99f408df40b659ec1b24d01bdae153b0802d7e53835
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
